#include "rasm/run/FloorPlan.h"
#include "rasm/core/Angles.h"

#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "rasm/surfel_map/MapExport.h"

namespace rasm::run {

namespace {

constexpr double kSnapDeg = 5.0;  // an up found without gravity snaps to a world axis this close
constexpr double kRefineConesDeg[] = {45.0, 20.0, 10.0};
constexpr std::size_t kMinHorizontalSurfels = 100;
constexpr double kFloorNormalDeg = 25.0;  // an upward-facing surfel for the floor's height
constexpr double kFloorBelowCameraM = 0.3;
constexpr double kFloorBinM = 0.02;
constexpr double kMarginM = 0.3;  // around everything drawn
constexpr int kPad = 12, kLegendW = 250, kLineH = 18, kMinWidth = 480;

const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGrid(215, 215, 215);
const cv::Scalar kFloorShade(232, 232, 232), kFurnitureShade(165, 165, 165), kWallShade(70, 70, 70);
const cv::Scalar kPath(200, 90, 20), kStart(40, 160, 40), kEnd(40, 40, 210);
const cv::Scalar kGoal(0, 140, 255);

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

cv::Scalar classScalar(int class_id) {
  const Bgr8 c = maps::labelColour(class_id);
  return {double(c.b), double(c.g), double(c.r)};
}

/// One thing drawn over the cells, in image pixels; rendered to the PNG and the SVG alike.
struct Shape {
  enum class Kind { Line, Polygon, Circle, Rect, Text } kind = Kind::Line;
  std::vector<cv::Point2d> pts;  ///< Line / Polygon: the vertices; Circle: centre; Rect: 2 corners
  cv::Scalar colour = kBlack;    ///< BGR
  double width = 1.0;            ///< stroke (px); Circle: radius is `size`
  double size = 0.0;             ///< Circle radius / Text height (px)
  bool filled = false;
  std::string text;
};

Shape line(std::vector<cv::Point2d> pts, const cv::Scalar& c, double w) {
  return {Shape::Kind::Line, std::move(pts), c, w, 0.0, false, {}};
}
Shape circle(const cv::Point2d& p, double r, const cv::Scalar& c, bool filled, double w = 1.5) {
  return {Shape::Kind::Circle, {p}, c, w, r, filled, {}};
}
Shape rect(const cv::Point2d& a, const cv::Point2d& b, const cv::Scalar& c, bool filled) {
  return {Shape::Kind::Rect, {a, b}, c, 1.0, 0.0, filled, {}};
}
Shape text(const cv::Point2d& baseline_left, const std::string& s, double height_px,
           const cv::Scalar& c = kBlack) {
  return {Shape::Kind::Text, {baseline_left}, c, 1.0, height_px, false, s};
}

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
double fontScale(double height_px) {
  return height_px / 22.0;
}
cv::Size textSize(const std::string& s, double height_px) {
  int base = 0;
  return cv::getTextSize(s, kFont, fontScale(height_px), 1, &base);
}

/// `s` in lines of at most width_px (broken at spaces; a longer word stands alone).
std::vector<std::string> wrapped(const std::string& s, int width_px, double height_px) {
  std::vector<std::string> lines;
  std::istringstream words(s);
  std::string word, line;
  while (words >> word) {
    const std::string longer = line.empty() ? word : line + " " + word;
    if (!line.empty() && textSize(longer, height_px).width > width_px) {
      lines.push_back(line);
      line = word;
    } else {
      line = longer;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

void renderPng(cv::Mat& img, const std::vector<Shape>& shapes) {
  for (const Shape& s : shapes) {
    std::vector<cv::Point> p;
    for (const cv::Point2d& q : s.pts) p.emplace_back(int(std::lround(q.x)), int(std::lround(q.y)));
    const int w = std::max(1, int(std::lround(s.width)));
    switch (s.kind) {
      case Shape::Kind::Line:
        cv::polylines(img, p, false, s.colour, w, cv::LINE_AA);
        break;
      case Shape::Kind::Polygon:
        if (s.filled) cv::fillPoly(img, std::vector<std::vector<cv::Point>>{p}, s.colour);
        cv::polylines(img, p, true, s.colour, w, cv::LINE_AA);
        break;
      case Shape::Kind::Circle:
        cv::circle(img, p[0], int(std::lround(s.size)), s.colour, s.filled ? cv::FILLED : w,
                   cv::LINE_AA);
        break;
      case Shape::Kind::Rect:
        cv::rectangle(img, p[0], p[1], s.colour, s.filled ? cv::FILLED : w);
        break;
      case Shape::Kind::Text:  // a white halo keeps it readable over the cells
        cv::putText(img, s.text, p[0], kFont, fontScale(s.size), kWhite, 3, cv::LINE_AA);
        cv::putText(img, s.text, p[0], kFont, fontScale(s.size), s.colour, 1, cv::LINE_AA);
        break;
    }
  }
}

std::string svgColour(const cv::Scalar& c) {
  char b[16];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", int(c[2]), int(c[1]), int(c[0]));
  return b;
}

std::string xmlEscaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string svgPoints(const std::vector<cv::Point2d>& pts) {
  std::ostringstream o;
  for (const cv::Point2d& p : pts) o << fmt("%.1f", p.x) << ',' << fmt("%.1f", p.y) << ' ';
  return o.str();
}

void svgShape(std::ostringstream& o, const Shape& s) {
  const std::string c = svgColour(s.colour), w = fmt("%.1f", s.width);
  switch (s.kind) {
    case Shape::Kind::Line:
      o << "<polyline points=\"" << svgPoints(s.pts) << "\" fill=\"none\" stroke=\"" << c
        << "\" stroke-width=\"" << w << "\" stroke-linejoin=\"round\"/>\n";
      break;
    case Shape::Kind::Polygon:
      o << "<polygon points=\"" << svgPoints(s.pts) << "\" fill=\"" << (s.filled ? c : "none")
        << "\" stroke=\"" << c << "\" stroke-width=\"" << w << "\"/>\n";
      break;
    case Shape::Kind::Circle:
      o << "<circle cx=\"" << fmt("%.1f", s.pts[0].x) << "\" cy=\"" << fmt("%.1f", s.pts[0].y)
        << "\" r=\"" << fmt("%.1f", s.size) << "\" fill=\"" << (s.filled ? c : "none")
        << "\" stroke=\"" << c << "\" stroke-width=\"" << w << "\"/>\n";
      break;
    case Shape::Kind::Rect: {
      const double x = std::min(s.pts[0].x, s.pts[1].x), y = std::min(s.pts[0].y, s.pts[1].y);
      o << "<rect x=\"" << fmt("%.1f", x) << "\" y=\"" << fmt("%.1f", y) << "\" width=\""
        << fmt("%.1f", std::abs(s.pts[1].x - s.pts[0].x)) << "\" height=\""
        << fmt("%.1f", std::abs(s.pts[1].y - s.pts[0].y)) << "\" fill=\"" << (s.filled ? c : "none")
        << "\" stroke=\"" << c << "\"/>\n";
      break;
    }
    case Shape::Kind::Text:
      o << "<text x=\"" << fmt("%.1f", s.pts[0].x) << "\" y=\"" << fmt("%.1f", s.pts[0].y)
        << "\" font-family=\"sans-serif\" font-size=\"" << fmt("%.1f", s.size * 1.35)
        << "\" fill=\"" << c << "\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\">"
        << xmlEscaped(s.text) << "</text>\n";
      break;
  }
}

std::string renderSvg(const cv::Mat& cells, const cv::Point& cells_at, const cv::Size& size,
                      const std::vector<Shape>& shapes) {
  std::vector<std::uint8_t> png;
  cv::imencode(".png", cells, png);
  std::string b64;
  mrpt::system::encodeBase64(png, b64);
  b64.erase(std::remove_if(b64.begin(), b64.end(), [](char c) { return std::isspace(c); }),
            b64.end());
  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size.width << "\" height=\""
    << size.height << "\" viewBox=\"0 0 " << size.width << ' ' << size.height << "\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<image x=\"" << cells_at.x << "\" y=\"" << cells_at.y << "\" width=\"" << cells.cols
    << "\" height=\"" << cells.rows
    << "\" style=\"image-rendering:pixelated\" href=\"data:image/png;base64," << b64 << "\"/>\n";
  for (const Shape& s : shapes) svgShape(o, s);
  o << "</svg>\n";
  return o.str();
}

/// Plan axes: x = the world axis least aligned with up, made horizontal; y = up x x.
Eigen::Matrix3d planRotation(const Eigen::Vector3d& up) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(up[i]) < std::abs(up[k]) - 1e-9) k = i;
  Eigen::Vector3d x = Eigen::Vector3d::Unit(k);
  x = (x - x.dot(up) * up).normalized();
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = up.cross(x).transpose();
  R.row(2) = up.transpose();
  return R;
}

/// The 8 corners of an object's box (world).
std::vector<Eigen::Vector3d> boxCorners(const ObjectBox& o) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3d d;
    for (int k = 0; k < 3; ++k) d[k] = ((i >> k) & 1 ? 0.5 : -0.5) * o.extents_m[k];
    c.push_back(o.centre_world + o.axes_world * d);
  }
  return c;
}

}  // namespace

FloorPlanUp floorPlanUp(const FloorPlanInput& in) {
  if (in.world_z_up) return {Eigen::Vector3d::UnitZ(), "up = world z (the simulator's world)"};
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::string how = "no camera pose";
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Isometry3d& T : in.T_world_cam) sum -= T.linear().col(1);
  if (sum.norm() > 1e-9) up = sum.normalized(), how = "the cameras' mean -y axis";
  // Refined by the horizontal surfaces (floor, table tops): the mean normal of the surfels
  // within a shrinking cone around the estimate (walls, 90 degrees off, never enter).
  const Eigen::Vector3d cameras_up = up;
  for (const double cone_deg : kRefineConesDeg) {
    const double c = std::cos(cone_deg * kRadPerDeg);
    Eigen::Vector3d n_sum = Eigen::Vector3d::Zero();
    std::size_t n = 0;
    for (const Eigen::Vector3f& nf : in.normals_world)
      if (nf.cast<double>().dot(up) >= c) n_sum += nf.cast<double>(), ++n;
    if (n < kMinHorizontalSurfels || n_sum.norm() < 1e-9) break;
    up = n_sum.normalized();
    how = "the horizontal surfaces' normal (" + std::to_string(n) + " surfels; " +
          fmt("%.1f", std::acos(std::clamp(up.dot(cameras_up), -1.0, 1.0)) / kRadPerDeg) +
          " deg from the cameras' up)";
  }
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(up[i]) > std::abs(up[k])) k = i;
  const Eigen::Vector3d axis = Eigen::Vector3d::Unit(k) * (up[k] < 0 ? -1.0 : 1.0);
  const double off_deg = std::acos(std::clamp(up.dot(axis), -1.0, 1.0)) / kRadPerDeg;
  const std::string name = std::string(up[k] < 0 ? "-" : "+") + "xyz"[k];
  if (off_deg <= kSnapDeg)
    return {axis, "up = world " + name + " (no gravity in the data: " + how + " is " +
                      fmt("%.1f", off_deg) + " deg from it)"};
  return {up, "up = " + how + ", " + fmt("%.1f", off_deg) + " deg from world " + name +
                  " (no gravity in the data)"};
}

double floorHeight(const FloorPlanInput& in, const Eigen::Vector3d& up) {
  if (in.points_world.empty()) return std::nan("");
  std::vector<double> cam_h;
  for (const Eigen::Isometry3d& T : in.T_world_cam) cam_h.push_back(up.dot(T.translation()));
  double below = INFINITY;
  if (!cam_h.empty()) {
    std::nth_element(cam_h.begin(), cam_h.begin() + cam_h.size() / 2, cam_h.end());
    below = cam_h[cam_h.size() / 2] - kFloorBelowCameraM;
  }
  const float cos_max = float(std::cos(kFloorNormalDeg * kRadPerDeg));
  std::map<long, int> bins;
  std::vector<double> all;
  for (std::size_t i = 0; i < in.points_world.size(); ++i) {
    const double h = up.dot(in.points_world[i].cast<double>());
    all.push_back(h);
    if (i < in.normals_world.size() && in.normals_world[i].cast<double>().dot(up) >= cos_max &&
        h <= below)
      ++bins[long(std::floor(h / kFloorBinM))];
  }
  if (bins.empty()) {
    std::nth_element(all.begin(), all.begin() + all.size() / 100, all.end());
    return all[all.size() / 100];
  }
  const auto best = std::max_element(
      bins.begin(), bins.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  return (double(best->first) + 0.5) * kFloorBinM;
}

Eigen::Vector2d FloorPlan::pixelOf(const Eigen::Vector3d& p_world) const {
  const Eigen::Vector3d q = R_plan_world * p_world;
  return {origin_px.x() + q.x() / metres_per_px, origin_px.y() - q.y() / metres_per_px};
}

namespace {

cv::Point2d pt(const Eigen::Vector2d& v) {
  return {v.x(), v.y()};
}
cv::Vec3b vec3b(const cv::Scalar& s) {
  return {std::uint8_t(s[0]), std::uint8_t(s[1]), std::uint8_t(s[2])};
}

/// The cells of the map area (see the header): one pixel per cell.
cv::Mat cellImage(const FloorPlanInput& in, const FloorPlan& plan, const FloorPlanParams& p,
                  const cv::Rect& area) {
  cv::Mat top(area.size(), CV_32F, cv::Scalar(-INFINITY));
  for (std::size_t i = 0; i < in.points_world.size(); ++i) {
    const Eigen::Vector3d w = in.points_world[i].cast<double>();
    const double h = plan.up.up_world.dot(w) - plan.floor_height_m;
    if (h > p.max_height_m) continue;
    const Eigen::Vector2d px = plan.pixelOf(w);
    const int cx = int(std::floor(px.x())) - area.x, cy = int(std::floor(px.y())) - area.y;
    // The surfel's disc seen from above: the cells within its radius of the centre's cell (at
    // most 3 on each side; a disc reaching past a cell's edge may cover its neighbour).
    const double r_px = i < in.radii_m.size() ? in.radii_m[i] / plan.metres_per_px : 0.0;
    const int r = std::clamp(int(std::ceil(r_px - 1e-3)), 0, 3);
    for (int y = std::max(0, cy - r); y <= std::min(area.height - 1, cy + r); ++y)
      for (int x = std::max(0, cx - r); x <= std::min(area.width - 1, cx + r); ++x) {
        float& t = top.at<float>(y, x);
        t = std::max(t, float(h));
      }
  }
  cv::Mat cells(area.size(), CV_8UC3, kWhite);
  for (int y = 0; y < cells.rows; ++y)
    for (int x = 0; x < cells.cols; ++x) {
      const float h = top.at<float>(y, x);
      if (!std::isfinite(h)) continue;
      const cv::Scalar& s =
          h < p.floor_band_m ? kFloorShade : (h < p.tall_m ? kFurnitureShade : kWallShade);
      cells.at<cv::Vec3b>(y, x) = vec3b(s);
    }
  return cells;
}

/// The 1 m grid, drawn into the cells that show no surface or the floor (walls stay whole).
void drawGrid(cv::Mat& cells, const FloorPlan& plan, const cv::Rect& area) {
  const double m = plan.metres_per_px;
  const cv::Vec3b white = vec3b(kWhite), floor = vec3b(kFloorShade), grid = vec3b(kGrid);
  const auto mark = [&](int x, int y) {
    cv::Vec3b& c = cells.at<cv::Vec3b>(y, x);
    if (c == white || c == floor) c = grid;
  };
  // Cell x covers plan x in [a, a + m): a grid line falls in it when a whole metre does.
  for (int x = 0; x < cells.cols; ++x) {
    const double a = (area.x + x - plan.origin_px.x()) * m;
    if (std::ceil(a) < a + m)
      for (int y = 0; y < cells.rows; ++y) mark(x, y);
  }
  for (int y = 0; y < cells.rows; ++y) {
    const double b = (plan.origin_px.y() - (area.y + y + 1)) * m;  // the cell's lower edge
    if (std::ceil(b) < b + m)
      for (int x = 0; x < cells.cols; ++x) mark(x, y);
  }
}

/// The scale bar, its left end at `a`: the longest of 0.5, 1, 2, 5, 10, 20 m within max_px.
void scaleBar(const FloorPlan& plan, const cv::Point2d& a, double max_px, std::vector<Shape>& out) {
  const double m = plan.metres_per_px;
  double len = 0.5;
  for (const double l : {1.0, 2.0, 5.0, 10.0, 20.0})
    if (l / m <= max_px) len = l;
  const cv::Point2d b(a.x + len / m, a.y);
  out.push_back(line({a, b}, kBlack, 3));
  out.push_back(line({{a.x, a.y - 6}, {a.x, a.y + 4}}, kBlack, 2));
  out.push_back(line({{b.x, b.y - 6}, {b.x, b.y + 4}}, kBlack, 2));
  out.push_back(text({a.x, a.y - 9}, fmt(len < 1 ? "%.1f m" : "%.0f m", len), 12));
}

void path(const FloorPlanInput& in, const FloorPlan& plan, std::vector<Shape>& out) {
  std::vector<cv::Point2d> pts;
  for (const Eigen::Isometry3d& T : in.T_world_cam)
    pts.push_back(pt(plan.pixelOf(T.translation())));
  if (pts.size() > 1) out.push_back(line(pts, kPath, 2));
}

/// Start, end and goals, drawn last: small, and never hidden under a label.
void markers(const FloorPlanInput& in, const FloorPlan& plan, std::vector<Shape>& out) {
  if (!in.T_world_cam.empty()) {
    out.push_back(circle(pt(plan.pixelOf(in.T_world_cam.front().translation())), 6, kStart, true));
    out.push_back(circle(pt(plan.pixelOf(in.T_world_cam.back().translation())), 6, kEnd, true));
  }
  const double h = plan.floor_height_m;
  for (const FloorPlanGoal& g : in.goals) {
    const Eigen::Vector2d c = plan.pixelOf({g.xy_yaw.x(), g.xy_yaw.y(), h});
    const Eigen::Vector2d tip = plan.pixelOf({g.xy_yaw.x() + 0.3 * std::cos(g.xy_yaw.z()),
                                              g.xy_yaw.y() + 0.3 * std::sin(g.xy_yaw.z()), h});
    out.push_back(line({pt(c), pt(tip)}, kGoal, 2));
    out.push_back(circle(pt(c), 4, kGoal, g.reached));
    if (!g.reached) {
      out.push_back(line({{c.x() - 5, c.y() - 5}, {c.x() + 5, c.y() + 5}}, kGoal, 2));
      out.push_back(line({{c.x() - 5, c.y() + 5}, {c.x() + 5, c.y() - 5}}, kGoal, 2));
    }
  }
}

/// Each object's outline from above and its label, placed where it overlaps no earlier label.
void objectShapes(const FloorPlanInput& in, const FloorPlan& plan, const cv::Rect& area,
                  std::vector<Shape>& out) {
  std::vector<cv::Rect2d> taken;
  for (const ObjectBox& o : in.objects) {
    std::vector<cv::Point2f> corners, hull;
    for (const Eigen::Vector3d& c : boxCorners(o)) {
      const Eigen::Vector2d p = plan.pixelOf(c);
      corners.emplace_back(float(p.x()), float(p.y()));
    }
    cv::convexHull(corners, hull);
    std::vector<cv::Point2d> poly(hull.begin(), hull.end());
    const cv::Scalar colour = classScalar(o.class_id);
    out.push_back({Shape::Kind::Polygon, poly, colour, 2.0, 0.0, false, {}});
    const cv::Rect2d box = cv::boundingRect(hull);
    const std::string label = o.class_name + " " + fmt("%.2f", o.probability);
    const cv::Size ts = textSize(label, 11);
    // Centred on the box, kept inside the map area.
    const double cx = std::clamp(box.x + box.width / 2 - ts.width / 2.0, double(area.x + 2),
                                 std::max(double(area.x + 2), area.br().x - ts.width - 2.0));
    cv::Rect2d at;
    for (double y : {box.y - 4, box.br().y + ts.height + 4, box.y + box.height / 2 + 5,
                     box.y - ts.height - 8, box.br().y + 2 * ts.height + 8}) {
      y = std::clamp(y, double(area.y + ts.height + 2), double(area.br().y - 2));
      at = cv::Rect2d(cx, y - ts.height, ts.width, ts.height + 2);
      if (std::none_of(taken.begin(), taken.end(),
                       [&](const cv::Rect2d& r) { return (r & at).area() > 0; }))
        break;
    }
    taken.push_back(at);
    out.push_back(text({at.x, at.br().y - 2}, label, 11, colour * 0.6));
  }
}

/// The legend column at x: cell shades, path, goals and each class shown (with its count).
/// Returns where it ends (y).
double legend(const FloorPlanInput& in, double x, double y, FloorPlan& plan,
              std::vector<Shape>& out) {
  const auto entry = [&](const std::string& s) {
    out.push_back(text({x + 26, y + 4}, s, 12));
    y += 20;
  };
  out.push_back(text({x, y + 4}, "Floor plan", 14));
  y += 26;
  for (const auto& [s, name] : {std::pair{kFloorShade, "floor"},
                                {kFurnitureShade, "furniture (below 1.2 m)"},
                                {kWallShade, "walls and tall things"}}) {
    out.push_back(rect({x, y - 7}, {x + 18, y + 5}, s, true));
    out.push_back(rect({x, y - 7}, {x + 18, y + 5}, kBlack, false));
    entry(name);
  }
  if (in.T_world_cam.size() > 1) {
    out.push_back(line({{x, y - 1}, {x + 18, y - 1}}, kPath, 2));
    entry("camera path");
    out.push_back(circle({x + 5, y - 1}, 5, kStart, true));
    out.push_back(circle({x + 15, y - 1}, 5, kEnd, true));
    entry("start, end");
  }
  if (!in.goals.empty()) {
    out.push_back(circle({x + 9, y - 1}, 4, kGoal, true));
    entry("goal reached (x: not)");
  }
  std::map<std::string, std::pair<int, int>> classes;  // name -> (class id, objects)
  for (const ObjectBox& o : in.objects) {
    auto& c = classes[o.class_name];
    c.first = o.class_id, ++c.second;
  }
  if (!classes.empty()) {
    y += 6;
    out.push_back(text({x, y + 4}, "Objects (class probability)", 12));
    y += 22;
  }
  for (const auto& [name, c] : classes) {
    out.push_back(rect({x, y - 7}, {x + 18, y + 5}, classScalar(c.first), true));
    entry(name + " (" + std::to_string(c.second) + ")");
  }
  plan.classes_shown = int(classes.size());
  return y;
}

}  // namespace

FloorPlan drawFloorPlan(const FloorPlanInput& in, const FloorPlanParams& params) {
  FloorPlan plan;
  if (in.points_world.empty() && in.T_world_cam.empty()) return plan;
  plan.up = floorPlanUp(in);
  const Eigen::Vector3d& up = plan.up.up_world;
  plan.floor_height_m = floorHeight(in, up);
  if (!std::isfinite(plan.floor_height_m)) plan.floor_height_m = 0.0;
  plan.R_plan_world = planRotation(up);
  // The extent of everything drawn, in plan coordinates.
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  const auto extend = [&](const Eigen::Vector3d& w) {
    const Eigen::Vector2d q = (plan.R_plan_world * w).head<2>();
    lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  };
  for (const Eigen::Vector3f& p : in.points_world) {
    const double h = up.dot(p.cast<double>()) - plan.floor_height_m;
    if (h <= params.max_height_m) extend(p.cast<double>());
  }
  for (const Eigen::Isometry3d& T : in.T_world_cam) extend(T.translation());
  for (const FloorPlanGoal& g : in.goals) extend({g.xy_yaw.x(), g.xy_yaw.y(), 0.0});
  for (const ObjectBox& o : in.objects)
    for (const Eigen::Vector3d& c : boxCorners(o)) extend(c);
  lo.array() -= kMarginM, hi.array() += kMarginM;
  const Eigen::Vector2d span = hi - lo;
  plan.metres_per_px = std::max(params.cell_m, span.maxCoeff() / params.max_size_px);
  const cv::Rect area(kPad, kPad, std::max(1, int(std::ceil(span.x() / plan.metres_per_px))),
                      std::max(1, int(std::ceil(span.y() / plan.metres_per_px))));
  plan.origin_px = {area.x - lo.x() / plan.metres_per_px, area.y + hi.y() / plan.metres_per_px};
  cv::Mat cells = cellImage(in, plan, params, area);
  drawGrid(cells, plan, area);

  std::vector<Shape> shapes;
  path(in, plan, shapes);
  objectShapes(in, plan, area, shapes);
  markers(in, plan, shapes);
  shapes.push_back(rect(area.tl(), area.br(), kBlack, false));
  const double legend_x = area.br().x + 2.0 * kPad;
  const double legend_end = legend(in, legend_x, area.y + 8.0, plan, shapes);
  scaleBar(plan, {legend_x + 4, legend_end + 24}, kLegendW - 3 * kPad, shapes);
  // The caption (title, how up was found, the floor) in lines that fit the plan's width.
  const int width = std::max(area.br().x + 2 * kPad + kLegendW, kMinWidth);
  std::vector<std::string> lines;
  if (!in.title.empty()) lines.push_back(in.title);
  const std::vector<std::string> caption =
      wrapped(plan.up.how + "; floor at " + fmt("%.2f m", plan.floor_height_m) + "; 1 m grid",
              width - 2 * kPad, 12);
  lines.insert(lines.end(), caption.begin(), caption.end());
  const int map_bottom = std::max(area.br().y, int(legend_end) + 40);
  const int height = map_bottom + kPad + kLineH * int(lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k)
    shapes.push_back(text({double(kPad), map_bottom + kLineH * (k + 1.0)}, lines[k], 12));
  const cv::Size size(width, height);

  plan.image = cv::Mat(size, CV_8UC3, kWhite);
  cells.copyTo(plan.image(area));
  renderPng(plan.image, shapes);
  plan.svg = renderSvg(cells, area.tl(), size, shapes);
  return plan;
}

std::vector<ObjectBox> objectBoxes(const nlohmann::json& doc) {
  std::vector<ObjectBox> out;
  if (!doc.is_object() || !doc.contains("objects") || !doc["objects"].is_array()) return out;
  const auto vec3 = [](const nlohmann::json& j) {
    return Eigen::Vector3d(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>());
  };
  for (const nlohmann::json& j : doc["objects"]) {
    if (!j.contains("oriented_box")) continue;
    const nlohmann::json& b = j["oriented_box"];
    ObjectBox o;
    o.id = j.value("id", 0);
    o.class_name = j.value("class", std::string("?"));
    o.class_id = j.value("class_id", 0);
    o.probability = j.value("probability", 0.0);
    o.centre_world = vec3(b.at("centre"));
    for (int k = 0; k < 3; ++k) o.axes_world.col(k) = vec3(b.at("axes").at(k));
    o.extents_m = vec3(b.at("extents_m"));
    out.push_back(o);
  }
  return out;
}

std::vector<FloorPlanGoal> floorPlanGoals(const nlohmann::json& doc) {
  std::vector<FloorPlanGoal> out;
  if (!doc.is_object() || !doc.contains("goals") || !doc["goals"].is_array()) return out;
  for (const nlohmann::json& j : doc["goals"]) {
    if (!j.contains("goal") || j["goal"].size() < 3) continue;
    FloorPlanGoal g;
    for (int k = 0; k < 3; ++k) g.xy_yaw[k] = j["goal"][std::size_t(k)].get<double>();
    g.reached = j.value("outcome", std::string()) == "reached";
    out.push_back(g);
  }
  return out;
}

}  // namespace rasm::run
