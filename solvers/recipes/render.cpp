// The software rasterizer of render.h: a deferred z-buffer pass (face id and barycentrics per
// subpixel), one shading pass, then lines (isolines, wireframe, curves) with a depth test, and a
// box filter down to the output size. Every step is serial double / float arithmetic in a fixed
// order, so the pixels do not depend on threads or hardware.
#include "solvers/recipes/render.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"

namespace ifem::solvers {

namespace {

constexpr double kPi = 3.14159265358979323846;
/// At most this many subpixels (width · height · supersample²): about 30 bytes each.
constexpr long long kMaxSubpixels = 1LL << 25;
constexpr float kSurfaceGrey[3] = {190.0f, 190.0f, 198.0f};
constexpr float kNoValueGrey[3] = {150.0f, 150.0f, 150.0f};
constexpr float kLineDark[3] = {25.0f, 25.0f, 25.0f};
constexpr float kWireGrey[3] = {60.0f, 60.0f, 70.0f};

struct Knot {
  double t;
  double rgb[3];
};

// Viridis-like: violet → blue → teal → green → yellow, luminance rising with t.
constexpr Knot kViridisKnots[] = {
    {0.000, {68, 1, 84}},    {0.125, {71, 44, 122}},  {0.250, {59, 81, 139}},
    {0.375, {44, 113, 142}}, {0.500, {33, 144, 141}}, {0.625, {39, 173, 129}},
    {0.750, {92, 200, 99}},  {0.875, {170, 220, 50}}, {1.000, {253, 231, 37}}};
constexpr Knot kDivergingKnots[] = {{0.00, {40, 70, 180}},
                                    {0.25, {120, 150, 225}},
                                    {0.50, {225, 225, 225}},
                                    {0.75, {230, 135, 110}},
                                    {1.00, {175, 20, 35}}};
constexpr Knot kGrayKnots[] = {{0.0, {0, 0, 0}}, {1.0, {255, 255, 255}}};

template <std::size_t N>
void interpolate(const Knot (&knots)[N], double t, double out[3]) {
  std::size_t i = 0;
  while (i + 2 < N && t > knots[i + 1].t) ++i;
  const double s = (t - knots[i].t) / (knots[i + 1].t - knots[i].t);
  for (int c = 0; c < 3; ++c)
    out[c] = knots[i].rgb[c] + s * (knots[i + 1].rgb[c] - knots[i].rgb[c]);
}

void map_color(ColorMap map, double t, double out[3]) {
  t = std::clamp(t, 0.0, 1.0);
  switch (map) {
    case ColorMap::kViridis:
      return interpolate(kViridisKnots, t, out);
    case ColorMap::kDiverging:
      return interpolate(kDivergingKnots, t, out);
    case ColorMap::kGray:
      return interpolate(kGrayKnots, t, out);
  }
}

/// Orthographic camera: screen x to the right, y down, depth growing towards the camera.
struct Camera {
  Eigen::Vector3d center, right, up, dir;
  double scale = 1.0;   // subpixels per scene unit
  double radius = 1.0;  // the scene's bounding radius about `center`
  double half_w = 0.0, half_h = 0.0;

  Eigen::Vector3d project(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = p - center;
    return {half_w + scale * q.dot(right), half_h - scale * q.dot(up), q.dot(dir)};
  }
};

/// The camera of a picture whose scene area is the first w columns (subpixels) of h rows.
Camera make_camera(const RenderScene& scene, const RenderOptions& o, int w, int h) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  auto grow = [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (Eigen::Index i = 0; i < scene.positions.rows(); ++i)
    grow(scene.positions.row(i).transpose());
  for (const auto& c : scene.curves)
    for (const auto& p : c) grow(p);
  Camera cam;
  cam.center = 0.5 * (lo + hi);
  double r2 = 0.0;
  for (Eigen::Index i = 0; i < scene.positions.rows(); ++i) {
    r2 = std::max(r2, (scene.positions.row(i).transpose() - cam.center).squaredNorm());
  }
  for (const auto& c : scene.curves)
    for (const auto& p : c) r2 = std::max(r2, (p - cam.center).squaredNorm());
  cam.radius = r2 > 0.0 ? std::sqrt(r2) : 1.0;
  const double a = o.azimuth_deg * kPi / 180.0, e = o.elevation_deg * kPi / 180.0;
  cam.dir = {std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a)};
  cam.right = {std::cos(a), 0.0, -std::sin(a)};
  cam.up = cam.dir.cross(cam.right);
  cam.half_w = 0.5 * w;
  cam.half_h = 0.5 * h;
  cam.scale = o.fill * 0.5 * std::min(w, h) / cam.radius;
  return cam;
}

/// The subpixel buffers: depth, the nearest face and its barycentrics, then the colour.
struct Canvas {
  int w = 0, h = 0;
  std::vector<float> depth;
  std::vector<Index> face;
  std::vector<float> b1, b2;
  std::vector<float> rgb;

  Canvas(int width, int height, const std::array<std::uint8_t, 3>& background)
      : w(width), h(height) {
    const std::size_t n = static_cast<std::size_t>(w) * h;
    depth.assign(n, -std::numeric_limits<float>::infinity());
    face.assign(n, -1);
    b1.assign(n, 0.0f);
    b2.assign(n, 0.0f);
    rgb.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) rgb[3 * i + c] = background[c];
    }
  }
};

void rasterize_triangle(Canvas& cv, Index f, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& p2) {
  const double area = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p1.y() - p0.y()) * (p2.x() - p0.x());
  if (!(std::abs(area) > 1e-12)) return;  // edge-on (or NaN)
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p0.x(), p1.x(), p2.x()}))));
  const int x1 =
      std::min(cv.w - 1, static_cast<int>(std::ceil(std::max({p0.x(), p1.x(), p2.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p0.y(), p1.y(), p2.y()}))));
  const int y1 =
      std::min(cv.h - 1, static_cast<int>(std::ceil(std::max({p0.y(), p1.y(), p2.y()}))));
  const double inv = 1.0 / area;
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      // barycentrics of p0..p2 from the signed areas of the opposite sub-triangles
      const double w1 =
          ((px - p0.x()) * (p2.y() - p0.y()) - (py - p0.y()) * (p2.x() - p0.x())) * inv;
      const double w2 =
          ((p1.x() - p0.x()) * (py - p0.y()) - (p1.y() - p0.y()) * (px - p0.x())) * inv;
      const double w0 = 1.0 - w1 - w2;
      if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
      const float z = static_cast<float>(w0 * p0.z() + w1 * p1.z() + w2 * p2.z());
      const std::size_t i = static_cast<std::size_t>(y) * cv.w + x;
      if (z > cv.depth[i]) {
        cv.depth[i] = z;
        cv.face[i] = f;
        cv.b1[i] = static_cast<float>(w1);
        cv.b2[i] = static_cast<float>(w2);
      }
    }
  }
}

/// Area-weighted vertex normals (zero for a vertex without faces).
std::vector<Eigen::Vector3d> vertex_normals(const RenderScene& s) {
  std::vector<Eigen::Vector3d> n(s.positions.rows(), Eigen::Vector3d::Zero());
  for (const Triangle& t : s.triangles) {
    const Eigen::Vector3d a = s.positions.row(t[0]), b = s.positions.row(t[1]),
                          c = s.positions.row(t[2]);
    const Eigen::Vector3d fn = (b - a).cross(c - a);
    for (Index v : t) n[v] += fn;
  }
  for (auto& v : n) {
    const double len = v.norm();
    if (len > 0.0) v /= len;
  }
  return n;
}

struct Shading {
  ColorMap map = ColorMap::kViridis;
  double lo = 0.0, hi = 1.0;
  bool has_field = false;
  Eigen::Vector3d light;
  double ambient = 0.3;

  void base_color(double v, double out[3]) const {
    if (!has_field) {
      for (int c = 0; c < 3; ++c) out[c] = kSurfaceGrey[c];
    } else if (!std::isfinite(v)) {
      for (int c = 0; c < 3; ++c) out[c] = kNoValueGrey[c];
    } else {
      map_color(map, (v - lo) / (hi - lo), out);
    }
  }
};

void shade_pixels(Canvas& cv, const RenderScene& s, const Shading& sh) {
  const std::vector<Eigen::Vector3d> normals = vertex_normals(s);
  const std::size_t n = static_cast<std::size_t>(cv.w) * cv.h;
  for (std::size_t i = 0; i < n; ++i) {
    const Index f = cv.face[i];
    if (f < 0) continue;
    const Triangle& t = s.triangles[f];
    const double w1 = cv.b1[i], w2 = cv.b2[i], w0 = 1.0 - w1 - w2;
    Eigen::Vector3d nrm = w0 * normals[t[0]] + w1 * normals[t[1]] + w2 * normals[t[2]];
    const double len = nrm.norm();
    const double lambert = len > 0.0 ? std::abs(nrm.dot(sh.light)) / len : 1.0;
    const double shade = sh.ambient + (1.0 - sh.ambient) * lambert;
    double v = 0.0;
    if (sh.has_field) {
      const double a = s.field[t[0]], b = s.field[t[1]], c = s.field[t[2]];
      v = (std::isfinite(a) && std::isfinite(b) && std::isfinite(c))
              ? w0 * a + w1 * b + w2 * c
              : std::numeric_limits<double>::quiet_NaN();
    }
    double col[3];
    sh.base_color(v, col);
    for (int c = 0; c < 3; ++c) cv.rgb[3 * i + c] = static_cast<float>(col[c] * shade);
  }
}

/// A square brush of `width` subpixels at (x, y), drawn where it is not behind the surface by
/// more than `bias` (depth units); `write_depth` for points, which occlude each other.
void stamp(Canvas& cv, double x, double y, double z, double width, double bias, const float col[3],
           bool write_depth) {
  const double r = 0.5 * width;
  const int xa = std::max(0, static_cast<int>(std::floor(x - r + 0.5)));
  const int xb = std::min(cv.w - 1, static_cast<int>(std::floor(x + r - 0.5)));
  const int ya = std::max(0, static_cast<int>(std::floor(y - r + 0.5)));
  const int yb = std::min(cv.h - 1, static_cast<int>(std::floor(y + r - 0.5)));
  const float zf = static_cast<float>(z + bias);
  for (int py = ya; py <= yb; ++py) {
    for (int px = xa; px <= xb; ++px) {
      const std::size_t i = static_cast<std::size_t>(py) * cv.w + px;
      if (zf < cv.depth[i]) continue;
      if (write_depth) cv.depth[i] = static_cast<float>(z);
      for (int c = 0; c < 3; ++c) cv.rgb[3 * i + c] = col[c];
    }
  }
}

struct Pen {
  double width = 1.0;  // subpixels
  double bias = 0.0;   // depth units
  float rgb[3] = {0, 0, 0};
};

void draw_segment(Canvas& cv, const Camera& cam, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Pen& pen) {
  const Eigen::Vector3d pa = cam.project(a), pb = cam.project(b);
  const double len = std::max(std::abs(pb.x() - pa.x()), std::abs(pb.y() - pa.y()));
  if (!std::isfinite(len)) return;
  const int steps = std::max(1, static_cast<int>(std::ceil(len)));
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector3d p = pa + (static_cast<double>(k) / steps) * (pb - pa);
    stamp(cv, p.x(), p.y(), p.z(), pen.width, pen.bias, pen.rgb, false);
  }
}

void draw_isolines(Canvas& cv, const Camera& cam, const RenderScene& s, const Shading& sh,
                   int count, const Pen& pen) {
  const double step = (sh.hi - sh.lo) / (count + 1);
  for (const Triangle& t : s.triangles) {
    const double v[3] = {s.field[t[0]], s.field[t[1]], s.field[t[2]]};
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) continue;
    const double vmin = std::min({v[0], v[1], v[2]}), vmax = std::max({v[0], v[1], v[2]});
    const int k0 = std::max(1, static_cast<int>(std::ceil((vmin - sh.lo) / step)));
    const int k1 = std::min(count, static_cast<int>(std::floor((vmax - sh.lo) / step)));
    for (int k = k0; k <= k1; ++k) {
      const double level = sh.lo + k * step;
      Eigen::Vector3d ends[2];
      int n = 0;
      for (int e = 0; e < 3 && n < 2; ++e) {
        const int i = e, j = (e + 1) % 3;
        if ((v[i] < level) == (v[j] < level)) continue;
        const double u = (level - v[i]) / (v[j] - v[i]);
        ends[n++] =
            (1.0 - u) * s.positions.row(t[i]).transpose() + u * s.positions.row(t[j]).transpose();
      }
      if (n == 2) draw_segment(cv, cam, ends[0], ends[1], pen);
    }
  }
}

void draw_wireframe(Canvas& cv, const Camera& cam, const RenderScene& s, const Pen& pen) {
  // an edge shared by two faces is drawn twice from the same end: the same pixels
  for (const Triangle& t : s.triangles) {
    for (int e = 0; e < 3; ++e) {
      const Index a = std::min(t[e], t[(e + 1) % 3]), b = std::max(t[e], t[(e + 1) % 3]);
      draw_segment(cv, cam, s.positions.row(a).transpose(), s.positions.row(b).transpose(), pen);
    }
  }
}

/// A point cloud's points as squares, without normals to light them: shaded by depth instead
/// (linearly, the farthest half as bright as the nearest with a field, a third without).
void draw_points(Canvas& cv, const Camera& cam, const RenderScene& s, const Shading& sh,
                 double size) {
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    const Eigen::Vector3d p = cam.project(s.positions.row(i).transpose());
    double col[3];
    sh.base_color(sh.has_field ? s.field[i] : 0.0, col);
    const double shade = (sh.has_field ? 0.75 : 0.5) + 0.25 * p.z() / cam.radius;
    const float c[3] = {static_cast<float>(col[0] * shade), static_cast<float>(col[1] * shade),
                        static_cast<float>(col[2] * shade)};
    stamp(cv, p.x(), p.y(), p.z(), size, 0.0, c, true);
  }
}

Image downsample(const Canvas& cv, int s) {
  Image img;
  img.width = cv.w / s;
  img.height = cv.h / s;
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
  const double norm = 1.0 / (s * s);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      double sum[3] = {0, 0, 0};
      for (int dy = 0; dy < s; ++dy) {
        for (int dx = 0; dx < s; ++dx) {
          const std::size_t i = static_cast<std::size_t>(y * s + dy) * cv.w + (x * s + dx);
          for (int c = 0; c < 3; ++c) sum[c] += cv.rgb[3 * i + c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        const double v = std::clamp(std::round(sum[c] * norm), 0.0, 255.0);
        img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3 + c] =
            static_cast<std::uint8_t>(v);
      }
    }
  }
  return img;
}

// ---- legend: a colour bar with its range written in a 5×7 pixel font ----

/// Rows of 5 pixels (bit 4 = leftmost) of the characters a "%.4g" number uses.
struct Glyph {
  char c;
  std::uint8_t rows[7];
};
constexpr Glyph kGlyphs[] = {
    {'0', {14, 17, 19, 21, 25, 17, 14}}, {'1', {4, 12, 4, 4, 4, 4, 14}},
    {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
    {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},
    {'6', {6, 8, 16, 30, 17, 17, 14}},   {'7', {31, 1, 2, 4, 8, 8, 8}},
    {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
    {'.', {0, 0, 0, 0, 0, 12, 12}},      {'-', {0, 0, 0, 31, 0, 0, 0}},
    {'+', {0, 4, 4, 31, 4, 4, 0}},       {'e', {0, 0, 14, 17, 31, 16, 14}}};

std::string legend_label(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

/// Pixel size of one font pixel: 1 up to 449 rows, then one more per 300 rows.
int legend_scale(int height) { return std::max(1, static_cast<int>(std::lround(height / 300.0))); }

int legend_width(int height, double lo, double hi) {
  const int k = legend_scale(height);
  const std::size_t chars = std::max(legend_label(lo).size(), legend_label(hi).size());
  return 4 * k + static_cast<int>(chars) * 6 * k + 3 * k + 8 * k + 4 * k;
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const std::uint8_t rgb[3]) {
  for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) {
      for (int c = 0; c < 3; ++c)
        img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3 + c] = rgb[c];
    }
  }
}

/// `text` right-aligned at column `right`, vertically centred on row `mid`.
void draw_text(Image& img, const std::string& text, int right, int mid, int k) {
  const std::uint8_t ink[3] = {20, 20, 20};
  int x = right - static_cast<int>(text.size()) * 6 * k + k;
  for (char ch : text) {
    for (const Glyph& g : kGlyphs) {
      if (g.c != ch) continue;
      for (int r = 0; r < 7; ++r) {
        for (int b = 0; b < 5; ++b) {
          if ((g.rows[r] >> (4 - b)) & 1) {
            const int px = x + b * k, py = mid - (7 * k) / 2 + r * k;
            fill_rect(img, px, py, px + k, py + k, ink);
          }
        }
      }
    }
    x += 6 * k;
  }
}

/// The colour bar (hi at the top) right of column img.width − legend_width, its range beside
/// it and a tick per isoline level.
void draw_legend(Image& img, const RenderOptions& o, double lo, double hi) {
  const int k = legend_scale(img.height);
  const int x1 = img.width - 4 * k, x0 = x1 - 8 * k;
  const int y0 = static_cast<int>(std::lround(0.1 * img.height));
  const int y1 = std::max(y0 + 2, static_cast<int>(std::lround(0.9 * img.height)));
  const std::uint8_t frame[3] = {20, 20, 20};
  fill_rect(img, x0 - 1, y0 - 1, x1 + 1, y1 + 1, frame);
  for (int y = y0; y < y1; ++y) {
    const auto c = colormap_color(o.colormap, 1.0 - (y - y0 + 0.5) / (y1 - y0));
    const std::uint8_t rgb[3] = {c[0], c[1], c[2]};
    fill_rect(img, x0, y, x1, y + 1, rgb);
  }
  for (int j = 1; j <= o.isolines; ++j) {
    const int y = y1 - static_cast<int>(std::lround((y1 - y0) * j / (o.isolines + 1.0)));
    fill_rect(img, x0, y, x1, y + 1, frame);
  }
  draw_text(img, legend_label(hi), x0 - 3 * k, y0, k);
  draw_text(img, legend_label(lo), x0 - 3 * k, y1, k);
}

/// The colour map's range: the options' when given, else the field's finite extent.
std::pair<double, double> field_range(const RenderScene& s, const RenderOptions& o) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (Eigen::Index i = 0; i < s.field.size(); ++i) {
    if (!std::isfinite(s.field[i])) continue;
    lo = std::min(lo, s.field[i]);
    hi = std::max(hi, s.field[i]);
  }
  if (!(lo <= hi)) lo = hi = 0.0;  // no finite value
  if (o.colormap == ColorMap::kDiverging) {
    const double m = std::max(std::abs(lo), std::abs(hi));
    lo = -m;
    hi = m;
  }
  if (!std::isnan(o.range_lo)) lo = o.range_lo;
  if (!std::isnan(o.range_hi)) hi = o.range_hi;
  if (!(lo < hi)) {  // a constant field: centred in the map
    const double pad = std::max(1.0, std::abs(lo)) * 0.5;
    lo -= pad;
    hi += pad;
  }
  return {lo, hi};
}

void check_range(const std::string& name, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi)) {
    throw InvalidInput("render: " + name + " must be in [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "], got " + std::to_string(v));
  }
}

void check_positive(const std::string& name, double v, double hi) {
  if (!(v > 0.0 && v <= hi)) {
    throw InvalidInput("render: " + name + " must be in (0, " + std::to_string(hi) + "], got " +
                       std::to_string(v));
  }
}

/// Wireframe, isolines and curves over the shaded surface. Lines sit on the surface: they pass
/// where the surface is at most a depth bias in front (1% of the scene's radius plus the pen's
/// half width at a 45° slope).
void draw_lines(Canvas& cv, const Camera& cam, const RenderScene& scene, const Shading& sh,
                const RenderOptions& o) {
  const int s = o.supersample;
  auto pen = [&](double width, const float rgb[3]) {
    Pen p;
    p.width = width * s;
    p.bias = 0.01 * cam.radius + 0.5 * p.width / cam.scale;
    for (int c = 0; c < 3; ++c) p.rgb[c] = rgb[c];
    return p;
  };
  if (o.wireframe) draw_wireframe(cv, cam, scene, pen(o.line_width, kWireGrey));
  if (o.isolines > 0) draw_isolines(cv, cam, scene, sh, o.isolines, pen(o.line_width, kLineDark));
  const float curve_rgb[3] = {static_cast<float>(o.curve_color[0]),
                              static_cast<float>(o.curve_color[1]),
                              static_cast<float>(o.curve_color[2])};
  const float intrinsic_rgb[3] = {static_cast<float>(o.intrinsic_color[0]),
                                  static_cast<float>(o.intrinsic_color[1]),
                                  static_cast<float>(o.intrinsic_color[2])};
  const Pen intrinsic_pen = pen(o.intrinsic_width, intrinsic_rgb);
  for (const auto& c : scene.intrinsic_edges) {
    for (std::size_t k = 1; k < c.size(); ++k) draw_segment(cv, cam, c[k - 1], c[k], intrinsic_pen);
  }
  const Pen glyph_pen = pen(o.line_width, kLineDark);
  for (const auto& g : scene.glyphs) draw_segment(cv, cam, g[0], g[1], glyph_pen);
  const Pen curve_pen = pen(o.curve_width, curve_rgb);
  for (const auto& c : scene.curves) {
    for (std::size_t k = 1; k < c.size(); ++k) draw_segment(cv, cam, c[k - 1], c[k], curve_pen);
  }
}

}  // namespace

void RenderScene::validate() const {
  const Index n = static_cast<Index>(positions.rows());
  if (n == 0) throw InvalidInput("render: the scene has no vertices");
  if (!positions.allFinite()) throw InvalidInput("render: a vertex position is not finite");
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    for (Index v : triangles[f]) {
      if (v < 0 || v >= n) {
        throw InvalidInput("render: face " + std::to_string(f) + " has vertex id " +
                           std::to_string(v) + ", outside [0, " + std::to_string(n) + ")");
      }
    }
  }
  if (field.size() != 0 && field.size() != n) {
    throw InvalidInput("render: the field " + (field_name.empty() ? "" : "'" + field_name + "' ") +
                       "has " + std::to_string(field.size()) + " values for " + std::to_string(n) +
                       " vertices");
  }
  auto check_lines = [](const auto& lines, const char* what) {
    for (std::size_t c = 0; c < lines.size(); ++c) {
      for (const auto& p : lines[c]) {
        if (!p.allFinite()) {
          throw InvalidInput(std::string("render: ") + what + " " + std::to_string(c) +
                             " has a non-finite point");
        }
      }
    }
  };
  check_lines(curves, "curve");
  check_lines(intrinsic_edges, "intrinsic edge");
  check_lines(glyphs, "glyph");
}

void RenderOptions::validate() const {
  check_range("width", width, 1, 16384);
  check_range("height", height, 1, 16384);
  check_range("supersample", supersample, 1, 4);
  const long long sub = 1LL * width * height * supersample * supersample;
  if (sub > kMaxSubpixels) {
    throw InvalidInput("render: width × height × supersample² = " + std::to_string(sub) +
                       " exceeds " + std::to_string(kMaxSubpixels) +
                       " (a smaller size or supersample)");
  }
  if (!std::isfinite(azimuth_deg)) throw InvalidInput("render: azimuth must be finite");
  check_range("elevation", elevation_deg, -90.0, 90.0);
  check_positive("fill", fill, 10.0);
  check_range("isolines", isolines, 0, 1000);
  check_positive("line width", line_width, 64.0);
  check_positive("curve width", curve_width, 64.0);
  check_positive("intrinsic edge width", intrinsic_width, 64.0);
  check_positive("point size", point_size, 64.0);
  check_range("ambient", ambient, 0.0, 1.0);
  if (std::isinf(range_lo) || std::isinf(range_hi)) {
    throw InvalidInput("render: the colour range must be finite");
  }
  if (!std::isnan(range_lo) && !std::isnan(range_hi) && !(range_lo < range_hi)) {
    throw InvalidInput("render: the colour range needs lo < hi, got [" + std::to_string(range_lo) +
                       ", " + std::to_string(range_hi) + "]");
  }
}

std::array<std::uint8_t, 3> Image::pixel(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

Rendering render_scene(const RenderScene& scene, const RenderOptions& o) {
  scene.validate();
  o.validate();
  const bool has_field = scene.field.size() > 0;
  if (o.isolines > 0 && !has_field) {
    throw InvalidInput("render: isolines need a field (a per-vertex property)");
  }
  if (o.legend && !has_field) throw InvalidInput("render: a legend needs a field");
  Shading sh;
  sh.map = o.colormap;
  sh.has_field = has_field;
  sh.ambient = o.ambient;
  Rendering out;
  out.range_lo = out.range_hi = std::numeric_limits<double>::quiet_NaN();
  if (has_field) std::tie(sh.lo, sh.hi) = field_range(scene, o);
  if (has_field) std::tie(out.range_lo, out.range_hi) = std::make_pair(sh.lo, sh.hi);
  out.scene_width = o.width;
  if (o.legend) {
    out.scene_width = o.width - legend_width(o.height, sh.lo, sh.hi);
    if (out.scene_width < o.height / 4 || out.scene_width < 1) {
      throw InvalidInput("render: the picture is too narrow for a legend (" +
                         std::to_string(o.width) + " pixels)");
    }
  }
  const int s = o.supersample;
  Canvas cv(o.width * s, o.height * s, o.background);
  const Camera cam = make_camera(scene, o, out.scene_width * s, cv.h);
  sh.light = (cam.dir + 0.5 * cam.up - 0.35 * cam.right).normalized();

  std::vector<Eigen::Vector3d> projected(scene.positions.rows());
  for (Eigen::Index i = 0; i < scene.positions.rows(); ++i) {
    projected[i] = cam.project(scene.positions.row(i).transpose());
  }
  for (std::size_t f = 0; f < scene.triangles.size(); ++f) {
    const Triangle& t = scene.triangles[f];
    rasterize_triangle(cv, static_cast<Index>(f), projected[t[0]], projected[t[1]],
                       projected[t[2]]);
  }
  shade_pixels(cv, scene, sh);
  if (scene.triangles.empty()) draw_points(cv, cam, scene, sh, o.point_size * s);
  draw_lines(cv, cam, scene, sh, o);
  out.image = downsample(cv, s);
  if (o.legend) draw_legend(out.image, o, sh.lo, sh.hi);
  return out;
}

std::array<double, 2> named_view(const std::string& name) {
  if (name == "front") return {0.0, 0.0};
  if (name == "back") return {180.0, 0.0};
  if (name == "right") return {90.0, 0.0};
  if (name == "left") return {-90.0, 0.0};
  if (name == "top") return {0.0, 90.0};
  if (name == "bottom") return {0.0, -90.0};
  throw InvalidInput("render: unknown view " + io::detail::quoted(name) +
                     " (front, back, left, right, top, bottom)");
}

ColorMap colormap_from_name(const std::string& name) {
  if (name == "viridis") return ColorMap::kViridis;
  if (name == "diverging") return ColorMap::kDiverging;
  if (name == "gray" || name == "grey") return ColorMap::kGray;
  throw InvalidInput("render: unknown colour map " + io::detail::quoted(name) +
                     " (viridis, diverging, gray)");
}

std::array<std::uint8_t, 3> colormap_color(ColorMap map, double t) {
  double c[3];
  map_color(map, t, c);
  return {static_cast<std::uint8_t>(std::lround(c[0])),
          static_cast<std::uint8_t>(std::lround(c[1])),
          static_cast<std::uint8_t>(std::lround(c[2]))};
}

}  // namespace ifem::solvers
