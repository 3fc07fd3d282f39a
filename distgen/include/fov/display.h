// The display an image is seen on: its pixels, how far the eye is from it and where the eye
// looks; the named displays every tool takes; and the one name a display's point-set files carry.
#pragma once

#include <string>
#include <vector>

namespace fov {

// A flat screen seen square-on from its centre. Viewing distance is in display widths.
struct display_geometry {
  int width = 1280;               // N: screen width in pixels
  int height = 1440;              // screen height in pixels
  double viewing_distance = 1.0;  // v: eye-to-screen distance / screen width
};

// The viewing distances every tool takes, in display widths: from 0.01 (a 178 degree field
// of view across the width) to 1000 (0.06 degrees); outside them pixels per degree and the
// eccentricities of the acuity model leave any display (a 1e-300 distance gave NaN FLIP).
constexpr double min_viewing_distance = 0.01, max_viewing_distance = 1000;
// "" when v lies in that range, else why not (naming the range).
std::string viewing_distance_problem(double v);

// The screen sides (pixels) a display spec may give.
constexpr int min_display_side = 8, max_display_side = 8192;

// Where the viewer looks: a screen position in pixels, continuous; (0, 0) is the top-left
// corner of the top-left pixel, y grows downwards. The one gaze type of every library and app.
struct gaze_point {
  double x = 0, y = 0;
  bool operator==(const gaze_point& o) const { return x == o.x && y == o.y; }
  bool operator!=(const gaze_point& o) const { return !(*this == o); }
};
inline gaze_point screen_centre(const display_geometry& d) { return {0.5 * d.width, 0.5 * d.height}; }

// Eccentricity (degrees) of screen pixel (x, y)'s centre seen with the gaze at `gaze`:
// atan(d / (W v)) for a screen W pixels wide viewed from v widths (thesis Eq. 1, s = 1).
double pixel_eccentricity_deg(const display_geometry& display, gaze_point gaze, int x, int y);

// Pixels per degree at the screen centre: W v pi / 180 (twice the thesis's Nyquist frequency,
// Eq. 3). It falls towards the edges of a flat screen.
double pixels_per_degree(const display_geometry& display);
// Fields of view across the screen's width and height, degrees.
double horizontal_fov_deg(const display_geometry& display);
double vertical_fov_deg(const display_geometry& display);
// The viewing distance (display widths) that gives a screen W pixels wide `ppd` pixels per
// degree at its centre, or a horizontal field of view of `fov_deg` degrees.
double viewing_distance_for_ppd(int width, double ppd);
double viewing_distance_for_fov(double fov_deg);

// A named display. Headsets are modelled as a flat screen per eye at their per-eye
// resolution, placed to give the pixels per degree the source states; a headset's lens spreads
// its pixels unevenly, so the flat screen's field of view (horizontal_fov_deg) is narrower than
// the headset's. docs/displays.md lists each with its source.
struct display_preset_info {
  const char* name;
  int width, height;
  double viewing_distance;  // > 0: given as a distance (the thesis's convention, v = 1)
  double ppd;               // > 0: the distance follows from these pixels per degree
  const char* what;         // one line: the device and the source of its figures
  display_geometry geometry() const;
};
const std::vector<display_preset_info>& display_presets();
// Their names, joined by ", " (help texts and messages).
std::string display_preset_names();

// Named displays. Returns false for an unknown name.
bool display_preset(const std::string& name, display_geometry& out);

// Parses a display spec, the one syntax every tool's --display takes:
//   NAME          a preset (display_presets())
//   WxH           W x H pixels seen from one display width (v = 1)
//   WxH@Nppd      ... placed to give N pixels per degree at the centre
//   WxH@Ndeg      ... placed to give a horizontal field of view of N degrees
//   WxH@V         ... seen from V display widths
// W and H lie in min_display_side..max_display_side, the distance in the viewing-distance range.
// Returns "" and sets `out`, or the reason the text is not a display (naming the forms).
std::string parse_display(const std::string& text, display_geometry& out);

// The name a display's point-set files carry: the preset's name when the geometry is a
// preset's, else WxH-vV (V to 4 significant digits: 640x720-v1, 3840x3840-v1.044).
std::string display_name(const display_geometry& display);

}  // namespace fov
