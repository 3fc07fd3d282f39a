#include "fov/fvvdp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "fov/colour.h"

namespace fov {

namespace {

constexpr double pi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------
// Contrast sensitivity. FovVideoVDP's CSF (paper Sec. 3.4): the achromatic sensitivity of
// the spatio-chromatic CSF of Mantiuk et al. (2020, "Practical color contrast sensitivity
// functions for luminance levels up to 10000 cd/m2"), a log-parabola in frequency whose
// peak and position depend on luminance, with Rovamo et al.'s (1993) stimulus-area term;
// eccentricity enters through cortical magnification (Dougherty et al. 2003), which scales
// frequency and stimulus size; temporal frequency through the ratio of Laird et al.'s
// (2006) spatio-velocity CSF at omega to the same at rest.

// The CSF's three mechanisms (achromatic, red-green, yellow-violet): luminance-dependent
// peak sensitivity and peak frequency, bandwidth, the area exponent gamma and the critical
// area Ac'. Values as fitted by Mantiuk et al. (2020).
struct mechanism {
  std::array<double, 5> s_max;
  int s_max_n;
  std::array<double, 3> f_max;
  int f_max_n;
  double bandwidth, gamma, ac_prime;
};
constexpr mechanism mechanisms[3] = {
    {{356404, 6.2726, 0.320031, 895943, 7.77919e-05}, 5, {2.3021, 3317.45, 0.186215}, 3, 1.07516, 1.1107, 52.9768},
    {{423.978, 15.4032, 0.50343}, 3, {0.122699}, 1, 2.70669, 1.72903, 1.38437},
    {{11811.9, 196.342, 0.339396}, 3, {7.1099e-08}, 1, 5.3416, 1.47263, 0.282573},
};
// Cone contrast (L, M, S) to the three mechanisms' contrasts (rows), with their signs.
constexpr double cone_to_mechanism[3][3] = {{1, 0.256197, 6.42477e-07},
                                            {1, -0.933541, 0.00373304},
                                            {-0.00130319, -1.1504, 1}};
// The luminance direction in LMS (CIE 2006 cone fundamentals) along which sensitivity is
// measured, and the LMS of a D65 background of unit luminance: CIE XYZ of D65 (0.95047, 1,
// 1.08883) through the XYZ-to-LMS2006 matrix for an LED LCD's spectra.
constexpr double luminance_direction[3] = {0.698, 0.302, 0.019613};
constexpr double xyz_to_lms[3][3] = {{0.187596268556126, 0.585168649077728, -0.026384263306304},
                                     {-0.133397430663221, 0.405505777260049, 0.034502127690364},
                                     {0.000244379021663, -0.000542995890619, 0.019406849066323}};
constexpr double d65_xyz[3] = {0.95047, 1.0, 1.08883};

// Luminance dependence of a mechanism's parameter: constant, or one or two hyperbolic terms.
double luminance_dependence(const double* p, int n, double lum) {
  switch (n) {
    case 1: return p[0];
    case 3: return p[0] * std::pow(1 + p[1] / lum, -p[2]);
    default: return p[0] * std::pow(1 + p[1] / lum, -p[2]) * (1 - std::pow(1 + p[3] / lum, -p[4]));
  }
}

// One mechanism's sensitivity at frequency f (cpd), stimulus area (deg^2), cone luminance lum.
double mechanism_sensitivity(int c, double f, double area, double lum) {
  const mechanism& m = mechanisms[c];
  const double s_max = luminance_dependence(m.s_max.data(), m.s_max_n, lum);
  const double f_max = luminance_dependence(m.f_max.data(), m.f_max_n, lum);
  double peak = s_max / std::pow(10.0, std::pow(std::log10(f) - std::log10(f_max), 2) / (0.5 * std::pow(2.0, m.bandwidth)));
  if (c > 0 && f < f_max) peak = s_max;  // the chromatic mechanisms are low-pass
  const double k = m.ac_prime + area * 0.65;
  const double a = std::pow(area, m.gamma) * f * f;
  return peak * std::sqrt(a / (k + a));
}

// Achromatic sensitivity (inverse threshold cone contrast) at luminance y (cd/m^2).
double achromatic_sensitivity(double f, double area, double y) {
  double lms[3], cc[3];
  for (int r = 0; r < 3; ++r)
    lms[r] = y * (xyz_to_lms[r][0] * d65_xyz[0] + xyz_to_lms[r][1] * d65_xyz[1] + xyz_to_lms[r][2] * d65_xyz[2]);
  const double lum = lms[0] + lms[1];
  double norm2 = 0;
  for (int r = 0; r < 3; ++r) cc[r] = luminance_direction[r] / lms[r], norm2 += cc[r] * cc[r];
  double c2 = 0;  // detection contrast of a unit-length stimulus, summed over mechanisms
  for (int m = 0; m < 3; ++m) {
    const double cm = std::abs(cone_to_mechanism[m][0] * cc[0] + cone_to_mechanism[m][1] * cc[1] +
                               cone_to_mechanism[m][2] * cc[2]);
    const double n = cm * mechanism_sensitivity(m, f, area, lum);
    c2 += n * n;
  }
  // The threshold is the stimulus scaled to detection contrast 1; sensitivity is the
  // inverse of its cone contrast's RMS over the three cones.
  return std::sqrt(c2) * std::sqrt(3.0) / std::sqrt(norm2);
}

// Laird et al.'s spatio-velocity CSF (velocity floored at 0.1 deg/s, the eye's drift).
double spatio_velocity_csf(double rho, double velocity) {
  constexpr double s1 = 6.1, s2 = 7.3, p1 = 45.9, c0 = 0.6329, c1 = 0.8404, c2 = 0.7986;
  const double v = std::max(velocity, 0.1);
  const double k = s1 + s2 * std::pow(std::abs(std::log10(c2 * v / 3)), 3);
  const double rho_max = p1 / (c2 * v + 2);
  return k * c0 * c1 * c2 * v * std::pow(c1 * 2 * pi * rho, 2) * std::exp(-(c1 * 4 * pi * rho) / rho_max);
}
double spatio_temporal_csf(double rho, double omega) { return spatio_velocity_csf(rho, omega / rho); }

// Cortical magnification (mm of V1 per degree) at eccentricity e, Dougherty et al. 2003.
double cortical_magnification(double e) { return 29.2 / (e + 3.67); }

// The table the metric reads the CSF from: log2 sensitivity on a 32^3 grid, uniform in
// log2 luminance (0.001..10000 cd/m^2), log2 frequency (1/16..64 cpd) and the square root
// of eccentricity (0..120 degrees), read by trilinear interpolation with queries clamped
// to the grid; the published model is calibrated with its CSF read this way.
class csf_table {
 public:
  static constexpr int n = 32;
  csf_table(double omega, const fvvdp_params& p) : log2_s_(size_t(n) * n * n) {
    for (int iy = 0; iy < n; ++iy)
      for (int ir = 0; ir < n; ++ir)
        for (int ie = 0; ie < n; ++ie) {
          const double y = std::exp2(y0 + (y1 - y0) * iy / (n - 1));
          const double rho = std::exp2(r0 + (r1 - r0) * ir / (n - 1));
          const double e = std::pow(e1 * ie / (n - 1), 2);
          const double s = std::max(fvvdp_csf(rho, omega, y, e, p), 1e-4);
          log2_s_[(size_t(iy) * n + ir) * n + ie] = float(std::log2(s));
        }
  }
  // log2 of the sensitivity at log2 frequency, log2 luminance, sqrt eccentricity.
  float lookup(float log2_rho, float log2_y, float sqrt_ecc) const {
    float fy, fr, fe;
    const int iy = cell(log2_y, float(y0), float(y1), fy), ir = cell(log2_rho, float(r0), float(r1), fr),
              ie = cell(sqrt_ecc, 0.0f, float(e1), fe);
    auto at = [&](int a, int b, int c) { return log2_s_[(size_t(a) * n + b) * n + c]; };
    auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    auto plane = [&](int c) {
      return lerp(lerp(at(iy, ir, c), at(iy, ir + 1, c), fr), lerp(at(iy + 1, ir, c), at(iy + 1, ir + 1, c), fr), fy);
    };
    return lerp(plane(ie), plane(ie + 1), fe);
  }

 private:
  // Grid bounds: log2 luminance, log2 frequency, sqrt eccentricity.
  static constexpr double y0 = -9.965784284662087, y1 = 13.287712379549449;  // log2(0.001), log2(10000)
  static constexpr double r0 = -4, r1 = 6;
  static constexpr double e1 = 10.954451150103322;  // sqrt(120)
  // The lower grid index of v (clamped to the grid) and the fraction towards the next.
  static int cell(float v, float lo, float hi, float& frac) {
    const float t = std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f) * (n - 1);
    const int i = std::min(int(t), n - 2);
    frac = t - float(i);
    return i;
  }
  std::vector<float> log2_s_;
};

// ---------------------------------------------------------------------------------------
// The pyramid (paper Sec. 3.3): a Laplacian pyramid with Burt and Adelson's 5-tap kernel
// (a = 0.4), reflected at the borders when reducing.

struct plane {
  int w = 0, h = 0;
  std::vector<float> v;
  plane() = default;
  plane(int w_, int h_) : w(w_), h(h_), v(size_t(w_) * h_) {}
  float* row(int y) { return v.data() + size_t(y) * w; }
  const float* row(int y) const { return v.data() + size_t(y) * w; }
};

constexpr float kernel[5] = {0.05f, 0.25f, 0.4f, 0.25f, 0.05f};

int reflect(int k, int n) { return k < 0 ? -1 - k : (k >= n ? 2 * n - 1 - k : k); }

// Blur and keep every second sample: ceil(w / 2) x ceil(h / 2).
plane reduce(const plane& x) {
  const int w2 = (x.w + 1) / 2, h2 = (x.h + 1) / 2;
  plane t(x.w, h2), y(w2, h2);
  tbb::parallel_for(0, h2, [&](int i) {
    float* out = t.row(i);
    std::fill(out, out + x.w, 0.0f);
    for (int k = 0; k < 5; ++k) {
      const float* in = x.row(reflect(2 * i + k - 2, x.h));
      for (int c = 0; c < x.w; ++c) out[c] += kernel[k] * in[c];
    }
    const float* in = t.row(i);
    float* o = y.row(i);
    for (int j = 0; j < w2; ++j) {
      float s = 0;
      for (int k = 0; k < 5; ++k) s += kernel[k] * in[reflect(2 * j + k - 2, x.w)];
      o[j] = s;
    }
  });
  return y;
}

// The inverse step: x upsampled to n samples by inserting zeros and blurring with twice the
// kernel. Beyond the ends the upsampled signal repeats the end samples at the next even
// positions (as the published decomposition pads it). out[j] for one axis:
// even j: 0.1 x[j/2 - 1] + 0.8 x[j/2] + 0.1 x[j/2 + 1]; odd j: 0.5 (x[(j-1)/2] + x[(j+1)/2]).
struct expand_taps {
  int a, b, c;  // sample indices
  float wa, wb, wc;
};
std::vector<expand_taps> expansion(int n_in, int n_out) {
  auto at = [&](int k) { return std::clamp(k, 0, n_in - 1); };
  std::vector<expand_taps> taps(static_cast<size_t>(n_out));
  for (int j = 0; j < n_out; ++j)
    if (j % 2 == 0)
      taps[size_t(j)] = {at(j / 2 - 1), j / 2, at(j / 2 + 1), 2 * kernel[0], 2 * kernel[2], 2 * kernel[4]};
    else
      taps[size_t(j)] = {at((j - 1) / 2), at((j + 1) / 2), 0, 2 * kernel[1], 2 * kernel[3], 0.0f};
  return taps;
}

plane expand(const plane& x, int w, int h) {
  const std::vector<expand_taps> tx = expansion(x.w, w), ty = expansion(x.h, h);
  plane y(w, h);
  tbb::parallel_for(0, h, [&](int r) {
    const expand_taps& t = ty[size_t(r)];
    const float *a = x.row(t.a), *b = x.row(t.b), *c = x.row(t.c);
    std::vector<float> col(size_t(x.w));
    for (int i = 0; i < x.w; ++i) col[size_t(i)] = t.wa * a[i] + t.wb * b[i] + t.wc * c[i];
    float* o = y.row(r);
    for (int j = 0; j < w; ++j) {
      const expand_taps& s = tx[size_t(j)];
      o[j] = s.wa * col[size_t(s.a)] + s.wb * col[size_t(s.b)] + s.wc * col[size_t(s.c)];
    }
  });
  return y;
}

// Band i = Gaussian level i minus the next level expanded; `expanded[i]` keeps that
// expansion (the reference's is the local adaptation luminance of band i).
struct pyramid {
  std::vector<plane> band, expanded;
};
pyramid decompose(plane image, int levels) {
  pyramid p;
  std::vector<plane> g;
  g.push_back(std::move(image));
  for (int i = 1; i < levels; ++i) g.push_back(reduce(g.back()));
  for (int i = 0; i + 1 < levels; ++i) {
    plane e = expand(g[size_t(i) + 1], g[size_t(i)].w, g[size_t(i)].h);
    plane b = std::move(g[size_t(i)]);
    for (size_t k = 0; k < b.v.size(); ++k) b.v[k] -= e.v[k];
    p.band.push_back(std::move(b));
    p.expanded.push_back(std::move(e));
  }
  p.band.push_back(std::move(g.back()));
  return p;
}

double lp_norm(const std::vector<double>& x, double p) {
  double s = 0;
  for (double v : x) s += std::pow(std::abs(v), p);
  return std::pow(s, 1 / p);
}

}  // namespace

double display_photometry::black() const { return peak / contrast + ambient_lux / pi * reflectivity; }

std::string photometry_problem(const display_photometry& p) {
  auto outside = [](double v, double lo, double hi) { return !(std::isfinite(v) && v >= lo && v <= hi); };
  if (outside(p.peak, 0.1, 10000)) return fmt::format("peak luminance must lie in 0.1..10000 cd/m^2 (got {:g})", p.peak);
  if (outside(p.contrast, 2, 1e6)) return fmt::format("contrast must lie in 2..1e6 (got {:g})", p.contrast);
  if (outside(p.ambient_lux, 0, 1e5)) return fmt::format("ambient light must lie in 0..1e5 lux (got {:g})", p.ambient_lux);
  if (outside(p.reflectivity, 0, 1)) return fmt::format("reflectivity must lie in 0..1 (got {:g})", p.reflectivity);
  return "";
}

double fvvdp_csf(double rho, double omega, double luminance, double eccentricity, const fvvdp_params& p) {
  const double sigma = p.csf_cycles / rho;  // a Gabor of csf_cycles cycles: its size in degrees
  const double m_rel = std::pow(cortical_magnification(eccentricity) / cortical_magnification(0), p.k_cm);
  const double area = pi * std::pow(sigma * m_rel, 2);
  const double rho_cm = rho / m_rel;
  const double temporal = spatio_temporal_csf(rho_cm, omega) / (spatio_temporal_csf(rho_cm, 0) + 1e-5);
  return achromatic_sensitivity(rho_cm, area, luminance) * temporal;
}

// ---------------------------------------------------------------------------------------

struct fvvdp::state {
  display_geometry display;
  double fps;
  display_photometry photometry;
  fvvdp_params params;
  double ppd;
  int levels;                        // Gaussian levels = bands (the last is the base band)
  std::vector<double> band_cpd;      // peak frequency per band
  std::vector<csf_table> csf;        // per temporal channel
  std::vector<float> temporal[2];    // filter taps: newest frame first
  std::deque<std::array<plane, 2>> history;  // luminance (test, reference), oldest first
  // Per frame: pooled difference per band and channel, foveated and not.
  std::vector<std::vector<double>> q_frames[2];
  std::array<float, 256> decode;     // 8-bit sRGB to linear

  plane luminance(const frame& f) const {
    plane l(f.width, f.height);
    const float black = float(photometry.black()), gain = float(photometry.peak - photometry.black());
    tbb::parallel_for(0, f.height, [&](int y) {
      float* o = l.row(y);
      for (int x = 0; x < f.width; ++x) {
        const glm::vec3& c = f.rgb[size_t(y) * f.width + x];
        float lin[3];
        for (int ch = 0; ch < 3; ++ch) lin[ch] = decode[display_byte(c[ch])];
        // sRGB primaries' luminance (IEC 61966-2-1)
        o[x] = gain * (0.2126729f * lin[0] + 0.7151522f * lin[1] + 0.0721750f * lin[2]) + black;
      }
    });
    return l;
  }

  // Screen geometry, as the published implementation models a flat screen seen from its
  // axis: a screen position's visual angle horizontally and vertically from the screen's
  // centre (atan(offset / (W v))), eccentricity the Euclidean norm of the two angles'
  // differences from the gaze's (for a gaze at the centre it is atan(d / (W v)) along either
  // axis), and a pixel's angular size shrinking off-centre: spatial frequencies in cycles
  // per degree grow there by (tan(a + delta) - tan(a)) / tan(delta), a its eccentricity from
  // the screen's centre, delta half a central pixel's angle. Per band: the angles of its
  // columns and rows (band pixels lie evenly on 0.5 .. W - 0.5) and log2 of that growth.
  struct band_geometry {
    std::vector<double> ax, ay;   // radians
    std::vector<float> log2_mag;  // row-major
  };
  std::vector<band_geometry> geometry;

  double distance_px() const { return double(display.width) * display.viewing_distance; }
  std::vector<double> axis_angles(int n_band, int n_screen) const {
    std::vector<double> a(static_cast<size_t>(n_band));
    const double step = n_band > 1 ? (n_screen - 1.0) / (n_band - 1) : 0;
    for (int j = 0; j < n_band; ++j) a[size_t(j)] = std::atan((0.5 + j * step - 0.5 * n_screen) / distance_px());
    return a;
  }
  void make_geometry(int w, int h) {
    band_geometry g;
    g.ax = axis_angles(w, display.width), g.ay = axis_angles(h, display.height);
    const double delta = std::atan(0.5 / distance_px());
    g.log2_mag.resize(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double a = std::min(std::hypot(g.ax[size_t(x)], g.ay[size_t(y)]), 89.9 * pi / 180);
        g.log2_mag[size_t(y) * w + x] = float(std::log2((std::tan(a + delta) - std::tan(a)) / std::tan(delta)));
      }
    geometry.push_back(std::move(g));
  }

  // One frame's channels (sustained test, sustained reference[, transient test, transient
  // reference]) through the pyramid, contrast, CSF and masking, pooled per band.
  void process(const std::vector<plane>& channels, gaze_point gaze) {
    const int n_ch = int(channels.size() / 2);
    std::vector<pyramid> pyr;
    for (const plane& c : channels) pyr.push_back(decompose(c, levels));
    const int n_bands = levels - 1;  // the base band is not pooled
    std::vector<double> q[2];
    const double corr = std::pow(10.0, params.sensitivity_correction / 20);
    const float mask_w = float(std::pow(10.0, params.mask_c));
    const double gaze_x = std::atan((gaze.x - 0.5 * display.width) / distance_px());
    const double gaze_y = std::atan((gaze.y - 0.5 * display.height) / distance_px());
    for (int cc = 0; cc < n_ch; ++cc) {
      const float w_ch = float(cc == 0 ? 1.0 : params.w_transient);
      const float q_mask = float(cc == 0 ? params.mask_q_sustained : params.mask_q_transient);
      const float p = float(params.mask_p), beta = float(params.beta);
      const csf_table& table = csf[size_t(cc)];
      for (int bb = 0; bb < n_bands; ++bb) {
        const float mul = (bb == 0) ? 1.0f : 2.0f;  // inner bands carry half their amplitude
        const plane& t = pyr[size_t(2 * cc)].band[size_t(bb)];
        const plane& r = pyr[size_t(2 * cc + 1)].band[size_t(bb)];
        const plane& adapt = pyr[1].expanded[size_t(bb)];  // the sustained reference's
        const int w = t.w, h = t.h;
        const float log2_rho = float(std::log2(band_cpd[size_t(bb)]));
        const band_geometry& geo = geometry[size_t(bb)];
        std::vector<double> row_sum[2] = {std::vector<double>(size_t(h)), std::vector<double>(size_t(h))};
        tbb::parallel_for(0, h, [&](int y) {
          double acc[2] = {0, 0};
          const float *tr = t.row(y), *rr = r.row(y), *ar = adapt.row(y), *mag = geo.log2_mag.data() + size_t(y) * w;
          const double gy = geo.ay[size_t(y)] - gaze_y;
          for (int x = 0; x < w; ++x) {
            const float l_bkg = ar[x];
            const float l_clamped = std::max(l_bkg, 0.1f);
            const float tc = std::min(mul * tr[x] / l_clamped, 1000.0f), rc = std::min(mul * rr[x] / l_clamped, 1000.0f);
            const float log2_y = std::log2(std::max(l_bkg, 1e-6f));
            // Foveated: sensitivity falls with eccentricity, frequencies in cycles per
            // degree grow off the screen's centre.
            const double e = std::hypot(geo.ax[size_t(x)] - gaze_x, gy) * 180 / pi;
            const float s_fov = float(corr) * std::exp2(table.lookup(log2_rho + mag[x], log2_y, float(std::sqrt(e))));
            const float s_nf = float(corr) * std::exp2(table.lookup(log2_rho, log2_y, 0.0f));
            const float s[2] = {s_fov, s_nf};
            for (int k = 0; k < 2; ++k) {
              const float a = tc * s[k], b = rc * s[k];
              const float m = std::min(std::abs(a), std::abs(b)) * mask_w;
              float d = std::pow(std::abs(a - b), p) / (1 + std::pow(m, q_mask));
              d = std::min(d, 1e4f);
              acc[k] += std::pow(d, beta);
            }
          }
          row_sum[0][size_t(y)] = acc[0], row_sum[1][size_t(y)] = acc[1];
        });
        for (int k = 0; k < 2; ++k) {
          double s = 0;
          for (double v : row_sum[k]) s += v;
          q[k].push_back(w_ch * std::pow(s / (double(w) * h), 1 / double(beta)));
        }
      }
    }
    for (int k = 0; k < 2; ++k) q_frames[k].push_back(std::move(q[k]));
  }
};

fvvdp::fvvdp(const display_geometry& display, double fps, const display_photometry& photometry, const fvvdp_params& params)
    : s_(std::make_unique<state>()) {
  if (display.width < 8 || display.height < 8)
    throw std::invalid_argument(fmt::format("FovVideoVDP needs images of at least 8x8 pixels (got {}x{})", display.width, display.height));
  if (const std::string why = viewing_distance_problem(display.viewing_distance); !why.empty())
    throw std::invalid_argument(why);
  if (!(fps == 0 || (fps >= 8 && fps <= 1000)))
    throw std::invalid_argument(fmt::format("frame rate must be 0 (images) or lie in 8..1000 (got {:g})", fps));
  if (const std::string why = photometry_problem(photometry); !why.empty()) throw std::invalid_argument(why);
  state& s = *s_;
  s.display = display, s.fps = fps, s.photometry = photometry, s.params = params;
  for (int i = 0; i < 256; ++i) s.decode[size_t(i)] = srgb_decode(float(i) / 255);
  // Pixels per degree at the centre: the inverse of the angle one central pixel subtends.
  s.ppd = 1 / (2 * std::atan(0.5 / (double(display.width) * display.viewing_distance)) * 180 / pi);
  // Bands: the finest at half the sampling rate, then 0.3228 of it halving per level, down
  // to the first at or below 0.5 cpd, and at most log2(smaller side) - 1 levels.
  const int max_levels = int(std::floor(std::log2(std::min(display.width, display.height)))) - 1;
  std::vector<double> freqs{s.ppd / 2};
  for (int k = 0; k < 14; ++k) freqs.push_back(0.3228 * std::pow(2.0, -k) * s.ppd / 2);
  int first_low = max_levels;
  for (size_t i = 0; i < freqs.size(); ++i)
    if (freqs[i] <= 0.5) {
      first_low = int(i);
      break;
    }
  const int height = std::clamp(first_low + 1, 0, max_levels);
  s.levels = height + 1;
  s.band_cpd.assign(freqs.begin(), freqs.begin() + s.levels);
  for (int i = 0, w = display.width, h = display.height; i + 1 < s.levels; ++i, w = (w + 1) / 2, h = (h + 1) / 2)
    s.make_geometry(w, h);
  s.csf.emplace_back(0.0, params);
  if (fps > 0) {
    s.csf.emplace_back(5.0, params);
    // Temporal filters over the last 250 ms: a log-normal sustained impulse response and,
    // for the transient channel, its scaled time derivative (paper Sec. 3.2).
    const int n = int(std::ceil(250.0 / (1000.0 / fps)));
    std::vector<double> t(static_cast<size_t>(n)), f0(static_cast<size_t>(n));
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      t[size_t(k)] = n > 1 ? (double(n) / fps) * k / (n - 1) : 0;
      f0[size_t(k)] = std::exp(-std::pow(std::log(t[size_t(k)] + 1e-4) - std::log(params.sustained_beta), 2) /
                               (2 * params.sustained_sigma * params.sustained_sigma));
      sum += f0[size_t(k)];
    }
    constexpr double k2 = 0.062170507756932;
    for (int k = 0; k < n; ++k) {
      s.temporal[0].push_back(float(f0[size_t(k)] / sum));
      s.temporal[1].push_back(k + 1 < n ? float(k2 * (f0[size_t(k) + 1] - f0[size_t(k)]) / sum / (t[1] - t[0])) : 0.0f);
    }
  }
}

fvvdp::~fvvdp() = default;

double fvvdp::ppd() const { return s_->ppd; }

void fvvdp::add(const frame& test, const frame& reference, gaze_point gaze) {
  state& s = *s_;
  for (const frame* f : {&test, &reference})
    if (f->width != s.display.width || f->height != s.display.height || f->rgb.size() != size_t(f->width) * f->height)
      throw std::invalid_argument(fmt::format("a {}x{} frame on a {}x{} display", f->width, f->height, s.display.width,
                                              s.display.height));
  if (s.fps == 0) {
    if (!s.q_frames[0].empty()) throw std::invalid_argument("an image comparison takes one pair of frames");
    s.process({s.luminance(test), s.luminance(reference)}, gaze);
    return;
  }
  std::array<plane, 2> now = {s.luminance(test), s.luminance(reference)};
  const size_t n = s.temporal[0].size();
  if (s.history.empty())
    while (s.history.size() + 1 < n) s.history.push_back(now);
  s.history.push_back(std::move(now));
  while (s.history.size() > n) s.history.pop_front();
  // Channels: sustained test, sustained reference, transient test, transient reference.
  std::vector<plane> channels(4, plane(s.display.width, s.display.height));
  for (int f = 0; f < 2; ++f)
    for (int i = 0; i < 2; ++i) {
      plane& out = channels[size_t(2 * f + i)];
      const std::vector<float>& taps = s.temporal[f];
      tbb::parallel_for(0, out.h, [&](int y) {
        float* o = out.row(y);
        for (size_t k = 0; k < n; ++k) {
          const float* in = s.history[n - 1 - k][size_t(i)].row(y);
          for (int x = 0; x < out.w; ++x) o[x] += taps[k] * in[x];
        }
      });
    }
  s.process(channels, gaze);
}

fvvdp_result fvvdp::result() const {
  const state& s = *s_;
  fvvdp_result r;
  r.frames = int(s.q_frames[0].size());
  r.bands = s.levels - 1;
  if (r.frames == 0) return r;
  const int n_ch = s.fps > 0 ? 2 : 1;
  double q[2];
  for (int k = 0; k < 2; ++k) {
    double frames_sum = 0;
    for (const std::vector<double>& per_frame : s.q_frames[k]) {
      std::vector<double> per_channel;
      for (int cc = 0; cc < n_ch; ++cc)
        per_channel.push_back(lp_norm(std::vector<double>(per_frame.begin() + cc * r.bands,
                                                          per_frame.begin() + (cc + 1) * r.bands),
                                      s.params.beta_bands));
      frames_sum += std::pow(lp_norm(per_channel, s.params.beta_channels), s.params.beta_frames);
    }
    q[k] = std::pow(frames_sum / r.frames, 1 / s.params.beta_frames);
  }
  auto jod = [&](double qq) { return 10 + s.params.jod_a * std::pow(qq, std::pow(10.0, s.params.log_jod_exp)); };
  r.q = q[0], r.q_nonfoveated = q[1];
  r.jod = jod(q[0]), r.jod_nonfoveated = jod(q[1]);
  return r;
}

fvvdp_result fvvdp_image(const frame& test, const frame& reference, const display_geometry& display, gaze_point gaze,
                         const display_photometry& photometry, const fvvdp_params& params) {
  fvvdp m(display, 0, photometry, params);
  m.add(test, reference, gaze);
  return m.result();
}

}  // namespace fov
