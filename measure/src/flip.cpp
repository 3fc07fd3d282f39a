#include "fov/flip.h"

#include "fov/bands.h"
#include "fov/colour.h"
#include "fov/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

namespace fov {

namespace {

constexpr double pi = 3.14159265358979323846;

// sRGB primaries, D65 white (IEC 61966-2-1): linear RGB to CIE XYZ and back.
constexpr double to_xyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                 {0.2126729, 0.7151522, 0.0721750},
                                 {0.0193339, 0.1191920, 0.9503041}};
constexpr double to_rgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                 {-0.9692660, 1.8760108, 0.0415560},
                                 {0.0556434, -0.2040259, 1.0572252}};
// The white point: XYZ of RGB (1, 1, 1).
constexpr double white[3] = {to_xyz[0][0] + to_xyz[0][1] + to_xyz[0][2], to_xyz[1][0] + to_xyz[1][1] + to_xyz[1][2],
                             to_xyz[2][0] + to_xyz[2][1] + to_xyz[2][2]};

// Three float planes of one image.
using planes = std::array<cv::Mat, 3>;

planes make_planes(int w, int h) { return {cv::Mat(h, w, CV_32F), cv::Mat(h, w, CV_32F), cv::Mat(h, w, CV_32F)}; }

// A frame as displayed (clamped, sRGB, 8 bits), decoded back to linear RGB.
planes displayed_linear(const frame& f) {
  std::array<float, 256> decode;
  for (int i = 0; i < 256; ++i) decode[size_t(i)] = srgb_decode(float(i) / 255);
  planes p = make_planes(f.width, f.height);
  tbb::parallel_for(0, f.height, [&](int y) {
    for (int x = 0; x < f.width; ++x) {
      const glm::vec3& c = f.rgb[size_t(y) * f.width + x];
      for (int ch = 0; ch < 3; ++ch)
        p[size_t(ch)].at<float>(y, x) = decode[display_byte(c[ch])];
    }
  });
  return p;
}

void apply(const double m[3][3], const double in[3], double out[3]) {
  for (int r = 0; r < 3; ++r) out[r] = m[r][0] * in[0] + m[r][1] * in[1] + m[r][2] * in[2];
}

// Linear RGB to the opponent space YyCxCz (XYZ relative to white, linear in light).
planes to_ycxcz(const planes& rgb) {
  planes out = make_planes(rgb[0].cols, rgb[0].rows);
  tbb::parallel_for(0, rgb[0].rows, [&](int y) {
    for (int x = 0; x < rgb[0].cols; ++x) {
      const double c[3] = {rgb[0].at<float>(y, x), rgb[1].at<float>(y, x), rgb[2].at<float>(y, x)};
      double xyz[3];
      apply(to_xyz, c, xyz);
      const double xr = xyz[0] / white[0], yr = xyz[1] / white[1], zr = xyz[2] / white[2];
      out[0].at<float>(y, x) = float(116 * yr - 16);
      out[1].at<float>(y, x) = float(500 * (xr - yr));
      out[2].at<float>(y, x) = float(200 * (yr - zr));
    }
  });
  return out;
}

double lab_f(double t) {
  constexpr double d = 6.0 / 29;
  return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29;
}

// Linear RGB (clamped to [0, 1]) to Hunt-adjusted L*a*b*: a* and b* scaled by L*/100,
// so chroma counts less in the dark.
std::array<double, 3> hunt_lab(const double rgb[3]) {
  double c[3], xyz[3];
  for (int i = 0; i < 3; ++i) c[i] = std::clamp(rgb[i], 0.0, 1.0);
  apply(to_xyz, c, xyz);
  const double fx = lab_f(xyz[0] / white[0]), fy = lab_f(xyz[1] / white[1]), fz = lab_f(xyz[2] / white[2]);
  const double l = 116 * fy - 16;
  return {l, 0.01 * l * 500 * (fx - fy), 0.01 * l * 200 * (fy - fz)};
}

// HyAB: |dL| + Euclidean distance in (a, b).
double hyab(const std::array<double, 3>& p, const std::array<double, 3>& q) {
  return std::fabs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

constexpr double colour_exponent = 0.7, feature_exponent = 0.5;
constexpr double cut_fraction = 0.4, cut_value = 0.95;  // the error redistribution's knee

// The largest colour difference on the display, green against blue, raised to qc: 1.
double colour_max() {
  const double green[3] = {0, 1, 0}, blue[3] = {0, 0, 1};
  return std::pow(hyab(hunt_lab(green), hunt_lab(blue)), colour_exponent);
}

// The paper's contrast-sensitivity filters, one per opponent channel: sums of Gaussians
// a sqrt(pi/b) exp(-pi^2 x^2 / b), x in degrees, normalised to sum 1 on the pixel grid.
struct csf_term {
  double a, b;
};
constexpr csf_term csf[3][2] = {{{1, 0.0047}, {0, 1e-5}},       // achromatic
                                {{1, 0.0053}, {0, 1e-5}},       // red-green
                                {{34.1, 0.04}, {13.5, 0.025}}};  // blue-yellow
constexpr double widest_b = 0.04;

cv::Mat filter_channel(const cv::Mat& in, int channel, double ppd) {
  const int r = int(std::ceil(3 * std::sqrt(widest_b / (2 * pi * pi)) * ppd));
  std::vector<cv::Mat> kernels;
  std::vector<double> weights;
  double total = 0;
  for (const csf_term& t : csf[channel]) {
    if (t.a == 0) continue;
    cv::Mat k(2 * r + 1, 1, CV_32F);
    double sum = 0;
    for (int i = -r; i <= r; ++i) {
      const double d = double(i) / ppd;
      const double v = std::exp(-pi * pi * d * d / t.b);
      k.at<float>(i + r) = float(v);
      sum += v;
    }
    const double w = t.a * std::sqrt(pi / t.b) * sum * sum;  // the term's 2D sum
    kernels.push_back(k / sum);
    weights.push_back(w);
    total += w;
  }
  cv::Mat out = cv::Mat::zeros(in.size(), CV_32F), tmp;
  for (size_t i = 0; i < kernels.size(); ++i) {
    cv::sepFilter2D(in, tmp, CV_32F, kernels[i], kernels[i], cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    out += tmp * (weights[i] / total);
  }
  return out;
}

// Edge (first derivative of a Gaussian) and point (second derivative) strength of the
// achromatic image: |(I * Gx, I * Gy)|. The Gaussian's standard deviation is half the
// paper's 0.082-degree width; each kernel's positive weights sum to 1, negative to -1.
std::array<cv::Mat, 2> features(const cv::Mat& lum, double ppd) {
  const double sd = 0.5 * 0.082 * ppd;
  const int r = int(std::ceil(3 * sd));
  cv::Mat g(2 * r + 1, 1, CV_32F), edge(2 * r + 1, 1, CV_32F), point(2 * r + 1, 1, CV_32F);
  double gsum = 0;
  for (int i = -r; i <= r; ++i) {
    const double v = std::exp(-double(i) * i / (2 * sd * sd));
    g.at<float>(i + r) = float(v);
    edge.at<float>(i + r) = float(-i * v);
    point.at<float>(i + r) = float((double(i) * i / (sd * sd) - 1) * v);
    gsum += v;
  }
  g /= gsum;
  for (cv::Mat* k : {&edge, &point}) {
    double pos = 0, neg = 0;
    for (int i = 0; i < k->rows; ++i) (k->at<float>(i) > 0 ? pos : neg) += k->at<float>(i);
    for (int i = 0; i < k->rows; ++i) {
      float& v = k->at<float>(i);
      if (v != 0) v = v > 0 ? float(v / pos) : float(v / -neg);  // (a kernel narrower than a pixel has zeros only)
    }
  }
  std::array<cv::Mat, 2> out;
  const cv::Mat* kernels[2] = {&edge, &point};
  for (int f = 0; f < 2; ++f) {
    cv::Mat fx, fy;
    cv::sepFilter2D(lum, fx, CV_32F, *kernels[f], g, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    cv::sepFilter2D(lum, fy, CV_32F, g, *kernels[f], cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    cv::magnitude(fx, fy, out[size_t(f)]);
  }
  return out;
}

// LDR-FLIP of two linear-RGB images at ppd.
cv::Mat flip_planes(const planes& test, const planes& ref, double ppd) {
  const planes t = to_ycxcz(test), r = to_ycxcz(ref);
  planes tf, rf;
  for (int c = 0; c < 3; ++c) tf[size_t(c)] = filter_channel(t[size_t(c)], c, ppd), rf[size_t(c)] = filter_channel(r[size_t(c)], c, ppd);
  // Features on the normalised achromatic channel (Yy + 16) / 116 = Y / Yw, unfiltered.
  const std::array<cv::Mat, 2> ft = features((t[0] + 16) / 116, ppd), fr = features((r[0] + 16) / 116, ppd);
  const double cmax = colour_max(), knee = cut_fraction * cmax;
  cv::Mat out(test[0].size(), CV_32F);
  tbb::parallel_for(0, out.rows, [&](int y) {
    for (int x = 0; x < out.cols; ++x) {
      auto back_to_rgb = [&](const planes& p, double rgb[3]) {
        const double yr = (p[0].at<float>(y, x) + 16.0) / 116;
        const double xyz[3] = {(yr + p[1].at<float>(y, x) / 500.0) * white[0], yr * white[1],
                               (yr - p[2].at<float>(y, x) / 200.0) * white[2]};
        apply(to_rgb, xyz, rgb);
      };
      double a[3], b[3];
      back_to_rgb(tf, a);
      back_to_rgb(rf, b);
      const double e = std::pow(hyab(hunt_lab(a), hunt_lab(b)), colour_exponent);
      const double colour = e < knee ? cut_value / knee * e : cut_value + (e - knee) / (cmax - knee) * (1 - cut_value);
      const double df = std::max(std::fabs(ft[0].at<float>(y, x) - fr[0].at<float>(y, x)),
                                 std::fabs(ft[1].at<float>(y, x) - fr[1].at<float>(y, x)));
      const double feature = std::pow(df / std::sqrt(2.0), feature_exponent);
      out.at<float>(y, x) = float(std::pow(std::min(colour, 1.0), 1 - feature));
    }
  });
  return out;
}

void check_pair(const frame& test, const frame& reference) {
  if (test.width != reference.width || test.height != reference.height || test.rgb.size() != reference.rgb.size())
    throw std::invalid_argument("frames differ in size");
  if (test.width < 1 || test.height < 1) throw std::invalid_argument("frames are empty");
}

error_map to_map(const cv::Mat& m) {
  error_map out;
  out.width = m.cols, out.height = m.rows;
  out.value.assign(m.begin<float>(), m.end<float>());
  return out;
}

// The foveated FLIP's pyramid: level j's map (at ppd 2^(j/2)), each at full size.
std::vector<cv::Mat> flip_levels(const frame& test, const frame& reference, double ppd, int levels) {
  const planes t = displayed_linear(test), r = displayed_linear(reference);
  std::vector<cv::Mat> out;
  for (int j = 0; j < levels; ++j) {
    const int down = 1 << (j / 2);
    const double level_ppd = ppd * (j % 2 ? std::sqrt(2.0) : 1.0);
    if (down == 1) {
      out.push_back(flip_planes(t, r, level_ppd));
      continue;
    }
    const cv::Size small(std::max(1, int(std::lround(double(test.width) / down))),
                         std::max(1, int(std::lround(double(test.height) / down))));
    planes ts, rs;
    for (size_t c = 0; c < 3; ++c)
      cv::resize(t[c], ts[c], small, 0, 0, cv::INTER_AREA), cv::resize(r[c], rs[c], small, 0, 0, cv::INTER_AREA);
    cv::Mat m;
    cv::resize(flip_planes(ts, rs, level_ppd), m, t[0].size(), 0, 0, cv::INTER_LINEAR);
    out.push_back(m);
  }
  return out;
}

void check_ppd(double ppd) {
  if (!(ppd > 0 && ppd <= 1000)) throw std::invalid_argument("pixels per degree must lie in (0, 1000]");
}

}  // namespace

double display_ppd(const display_geometry& d) { return double(d.width) * d.viewing_distance * pi / 180; }

error_map flip_map(const frame& test, const frame& reference, double ppd) {
  check_pair(test, reference);
  check_ppd(ppd);
  return to_map(flip_planes(displayed_linear(test), displayed_linear(reference), ppd));
}

double foveated_ppd(double ppd, const acuity_params& acuity, double e) {
  return ppd * cutoff_frequency_cpd(acuity, 0) / cutoff_frequency_cpd(acuity, e);
}

namespace {

struct foveated_result {
  cv::Mat flip, foveated;
};

foveated_result foveated_maps(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                              int max_levels) {
  check_pair(test, reference);
  const double ppd = display_ppd(eye.display);
  check_ppd(ppd);
  const int w = test.width, h = test.height;
  // Each pixel's level position t = 2 log2(ppd_e / ppd), tabulated per 0.01 degree.
  std::vector<double> level_of(9001);
  for (size_t i = 0; i < level_of.size(); ++i)
    level_of[i] = 2 * std::log2(foveated_ppd(ppd, eye.acuity, double(i) * 0.01) / ppd);
  cv::Mat position(h, w, CV_32F);
  double deepest = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double e = pixel_eccentricity_deg(eye.display, gaze, x, y);
      const double t = level_of[std::min(level_of.size() - 1, size_t(e * 100 + 0.5))];
      position.at<float>(y, x) = float(t);
      deepest = std::max(deepest, t);
    }
  int levels = std::min(max_levels, int(std::ceil(deepest)) + 1);
  while (levels > 1 && std::min(w, h) / (1 << ((levels - 1) / 2)) < 8) --levels;
  levels = std::max(levels, 1);
  const std::vector<cv::Mat> maps = flip_levels(test, reference, ppd, levels);
  foveated_result out{maps[0], cv::Mat(h, w, CV_32F)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double t = std::clamp(double(position.at<float>(y, x)), 0.0, double(levels - 1));
      const int i = std::min(int(t), levels - 1), j = std::min(i + 1, levels - 1);
      const double f = t - i;
      out.foveated.at<float>(y, x) = float((1 - f) * maps[size_t(i)].at<float>(y, x) + f * maps[size_t(j)].at<float>(y, x));
    }
  return out;
}

}  // namespace

error_map foveated_flip_map(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                            int max_levels) {
  return to_map(foveated_maps(test, reference, eye, gaze, max_levels).foveated);
}

pooled_error pool_error(const error_map& map, const display_geometry& display, gaze_point gaze,
                        const std::vector<double>& edges) {
  if (map.value.size() != size_t(map.width) * size_t(map.height) || map.value.empty())
    throw std::invalid_argument("error map is empty or malformed");
  if (map.width != display.width || map.height != display.height)
    throw std::invalid_argument("error map and display differ in size");
  const eccentricity_bands bands(display, gaze, edges);
  pooled_error p;
  p.edges_deg = edges;
  std::vector<double> sums(bands.count(), 0.0);
  p.pixels.assign(bands.count(), 0);
  double total = 0;
  bands.for_each_pixel(map.width, map.height, [&](int x, int y, double, size_t band) {
    const double v = map.value[size_t(y) * map.width + x];
    sums[band] += v, ++p.pixels[band], total += v;
  });
  p.mean = total / double(map.value.size());
  p.worst_band = 0;
  for (size_t b = 0; b < sums.size(); ++b) {
    p.bands.push_back(p.pixels[b] ? sums[b] / double(p.pixels[b]) : std::numeric_limits<double>::quiet_NaN());
    if (p.pixels[b]) p.worst_band = std::max(p.worst_band, p.bands.back());
  }
  std::vector<float> sorted = map.value;
  const size_t at = std::min(sorted.size() - 1, size_t(std::ceil(0.99 * double(sorted.size()))) - 1);
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(at), sorted.end());
  p.p99 = sorted[at];
  return p;
}

flip_report measure_flip(const frame& test, const frame& reference, const spacing_model& eye, gaze_point gaze,
                         const std::vector<double>& edges, bool keep_maps) {
  const foveated_result maps = foveated_maps(test, reference, eye, gaze, 16);
  flip_report r;
  r.ppd = display_ppd(eye.display);
  error_map plain = to_map(maps.flip), foveated = to_map(maps.foveated);
  r.flip = pool_error(plain, eye.display, gaze, edges);
  r.foveated = pool_error(foveated, eye.display, gaze, edges);
  if (keep_maps) r.flip_map = std::move(plain), r.foveated_map = std::move(foveated);
  return r;
}

}  // namespace fov
