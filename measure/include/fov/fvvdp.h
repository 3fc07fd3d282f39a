// FovVideoVDP: the visible-difference predictor for wide field-of-view images and video of
// Mantiuk, Denes, Chapiro, Kaplanyan, Rufo, Bachy, Lian and Patney (ACM TOG 40(4) 49, 2021),
// written from the paper and checked against values of its published implementation
// (../shared/metric-validation, docs/metrics.md). Quality is in JOD: 10 means no visible
// difference, and configurations 1 JOD apart are told apart by 75 % of observers.
//
// The model, in the order a frame goes through it: display photometry (pixel values to
// absolute luminance), sustained and transient temporal channels (video only), a Laplacian
// pyramid per channel, local Weber contrast against the reference's next coarser Gaussian
// level, a contrast sensitivity function of spatial and temporal frequency, luminance and
// eccentricity (with cortical magnification), mutual masking between test and reference,
// pooling over pixels, bands, channels and frames, and a regression to JOD.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "fov/acuity.h"
#include "fov/frame.h"

namespace fov {

// The display's light: a gain-offset model with the sRGB transfer function. A displayed
// pixel's luminance is (peak - black) x linear + black, black = peak / contrast + the
// ambient light the screen reflects (ambient / pi x reflectivity). The defaults are those
// of the validation set (FovVideoVDP's `standard_hmd` photometry without ambient light).
struct display_photometry {
  double peak = 100;            // cd/m^2
  double contrast = 1000;       // peak : black of the panel in the dark
  double ambient_lux = 0;       // illuminance on the screen
  double reflectivity = 0.005;  // share of the ambient light the screen reflects
  double black() const;         // cd/m^2
};
// "" when a photometry is usable (finite, peak 0.1..10000 cd/m^2, contrast 2..1e6, ambient
// 0..1e5 lux, reflectivity 0..1), else why not, naming the quantity and the range.
std::string photometry_problem(const display_photometry& p);

// The model's calibrated constants: FovVideoVDP v1.2's (pyfvvdp's
// fvvdp_data/fvvdp_parameters.json, calibration of 20/11/2021; docs/metrics.md cites each).
struct fvvdp_params {
  double mask_p = 2.4;                   // exponent of the masked difference
  double mask_c = -0.973838;             // log10 weight of the mutual masking signal
  double mask_q_sustained = 2.43685;     // masking exponent, sustained channel
  double mask_q_transient = 4.946;       // masking exponent, transient channel
  double w_transient = 0.25;             // weight of the transient channel
  double beta = 1.52134;                 // pooling exponent over pixels
  double beta_frames = 1;                // over frames (a mean)
  double beta_channels = 0.666092;       // over the temporal channels
  double beta_bands = 1;                 // over the bands of the pyramid
  double sustained_sigma = 0.5;          // sustained filter: log-normal width
  double sustained_beta = 0.06;          // and peak time, seconds
  double csf_cycles = 1.5;               // CSF stimulus: a Gabor of this many cycles
  double sensitivity_correction = 16.2596;  // dB added to the CSF
  double k_cm = 0.604562;                // exponent of cortical magnification's effect
  double jod_a = -0.0161713;             // JOD = 10 + jod_a Q^(10^log_jod_exp)
  double log_jod_exp = -0.2280;
};

// Contrast sensitivity (1 / threshold Weber contrast) of the model's CSF before the
// sensitivity correction: spatial frequency rho (cycles per degree), temporal frequency
// omega (Hz; 0 sustained, 5 transient), background luminance (cd/m^2) and eccentricity
// (degrees). Not clamped to the ranges the metric's table covers.
double fvvdp_csf(double rho_cpd, double omega_hz, double luminance, double eccentricity_deg,
                 const fvvdp_params& p = {});

// The two ways of looking at the frames: foveated (gaze at the given point of each frame,
// sensitivity falling with eccentricity) and non-foveated (every pixel seen foveally, the
// metric's default and the stricter one). A comparison gives both at once.
struct fvvdp_result {
  double jod = 10, jod_nonfoveated = 10;
  double q = 0, q_nonfoveated = 0;  // pooled difference before the JOD regression
  int frames = 0, bands = 0;        // frames seen; pyramid bands pooled (the base band is not)
};

// One comparison of a test and a reference sequence of frames, fed frame by frame
// (O(filter length) frames held). `fps` 0 compares images: one pair, no temporal channels.
// Frames are taken as displayed, like the FLIP of flip.h: linear RGB clamped to [0, 1],
// sRGB-encoded and quantised to 8 bits; luminance by the sRGB primaries. The first frame
// is repeated before the sequence to fill the temporal filters (250 ms).
class fvvdp {
 public:
  // Throws std::invalid_argument for a display under 8 pixels either way, a viewing
  // distance outside acuity.h's range, fps outside 0 or 1..1000, or a photometry_problem.
  fvvdp(const display_geometry& display, double fps = 0, const display_photometry& photometry = {},
        const fvvdp_params& params = {});
  ~fvvdp();
  fvvdp(const fvvdp&) = delete;
  fvvdp& operator=(const fvvdp&) = delete;

  // Adds a frame pair seen with the gaze at `gaze` (screen pixels, acuity.h's convention).
  // Throws std::invalid_argument for frames not of the display's size or a second pair
  // given to an image comparison.
  void add(const frame& test, const frame& reference, gaze_point gaze);
  // The quality of what was added so far (10 for nothing).
  fvvdp_result result() const;
  // Pixels per degree at the screen's centre, the frequency scale of the pyramid's bands.
  double ppd() const;

 private:
  struct state;
  std::unique_ptr<state> s_;
};

// An image pair: fvvdp with fps 0, one add.
fvvdp_result fvvdp_image(const frame& test, const frame& reference, const display_geometry& display, gaze_point gaze,
                         const display_photometry& photometry = {}, const fvvdp_params& params = {});

}  // namespace fov
