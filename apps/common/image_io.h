// Frames to and from image files through OpenImageIO.
#pragma once

#include <string>

#include "fov/frame.h"

namespace fov {

// By extension: .exr keeps linear float RGB, and the depth as channel Z when the frame
// has one; anything else (.png, .jpg, ...) is clamped
// to [0, 1] and sRGB-encoded at 8 bits. Written to a temporary file, then renamed.
// Throws file_error naming the path.
void write_frame(const frame& f, const std::string& path);

// The largest linear value an image read for measurement may hold: the largest half float
// (what OpenEXR's common half channels hold); fovray's frames are display values near 1.
constexpr float max_image_value = 65504.0f;

// "" when write_frame can write `path`'s format (its extension names one OpenImageIO
// writes), else why not: checked before a tool renders anything.
std::string image_format_problem(const std::string& path);

// Reads RGB (and depth from a channel Z, else none); 8-bit images are sRGB-decoded to linear.
// Every image read here is measured (compare, --compare, fovbench's cached references), so
// one whose colour values are not all finite and within [0, max_image_value], or whose
// depth is NaN or negative (+inf, no hit, is fine), is refused with the count of such
// pixels and the first one's position: a metric over them would be a number, silently
// wrong. Throws file_error naming the path.
frame read_frame(const std::string& path);

}  // namespace fov
