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

// Reads RGB (and depth from a channel Z, else none); 8-bit images are sRGB-decoded to linear. Throws file_error naming the path.
frame read_frame(const std::string& path);

}  // namespace fov
