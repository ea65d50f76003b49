#include "hedra/render/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hedra {
namespace {

std::string colour(const Vec3& c) {
  char buf[16];
  const auto byte = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", byte(c.x()), byte(c.y()), byte(c.z()));
  return buf;
}

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// One path of the segments of `kind`: "M x y L x y" per segment, in pixels (0.01 px).
template <class ToPixels>
std::string path(const std::vector<HlrSegment>& segments, const ToPixels& to_pixels,
                 const std::vector<LineKind>& kinds) {
  std::string d;
  char buf[96];
  for (const HlrSegment& s : segments) {
    if (std::find(kinds.begin(), kinds.end(), s.kind) == kinds.end()) continue;
    const Vec2 a = to_pixels(s, true), b = to_pixels(s, false);
    std::snprintf(buf, sizeof buf, "M%.2f %.2fL%.2f %.2f", a.x(), a.y(), b.x(), b.y());
    d += buf;
  }
  return d;
}

}  // namespace

PictureFit fit_picture(const Eigen::AlignedBox2d& box, int width, int height, double margin) {
  PictureFit fit;
  fit.height = height;
  const double w = width * (1 - 2 * margin), h = height * (1 - 2 * margin);
  const Vec2 size = box.isEmpty() ? Vec2(0, 0) : Vec2(box.sizes());
  const double sx = size.x() > 0 ? w / size.x() : INFINITY, sy = size.y() > 0 ? h / size.y() : INFINITY;
  fit.scale = std::min(sx, sy);
  if (!std::isfinite(fit.scale)) fit.scale = 1;
  const Vec2 centre = box.isEmpty() ? Vec2(0, 0) : Vec2(box.center());
  fit.offset = Vec2(0.5 * width, 0.5 * height) - fit.scale * centre;
  return fit;
}

std::string hidden_lines_svg(const HlrResult& result, const SvgStyle& style) {
  // World points through the renderer's view, or picture-plane points fitted to the image.
  const SvgFrame frame(style, result);
  const auto to_pixels = [&](const HlrSegment& s, bool first) -> Vec2 {
    return first ? frame.pixels(s.a, s.a2) : frame.pixels(s.b, s.b2);
  };
  std::string out;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                "viewBox=\"0 0 %d %d\">\n",
                style.width, style.height, style.width, style.height);
  out += buf;
  if (!style.title.empty()) out += "<title>" + escape(style.title) + "</title>\n";
  // Stroke widths in pixels: the drawing is in pixel units, and non-scaling-stroke keeps them
  // when the SVG itself is scaled.
  std::snprintf(buf, sizeof buf,
                "<style>\n"
                "  path { fill: none; stroke-linecap: round; stroke-linejoin: round; "
                "vector-effect: non-scaling-stroke; }\n"
                "  .visible { stroke: #000000; stroke-width: %gpx; }\n"
                "  .junction { stroke: #b2182b; stroke-width: %gpx; }\n"
                "  .hidden { stroke: #7f7f7f; stroke-width: %gpx; stroke-dasharray: %g %g; }\n",
                style.visible_px, style.junction_px, style.hidden_px, 4 * style.hidden_px,
                3 * style.hidden_px);
  out += buf;
  // Classes of smooth bodies only where the scene has them: a polyhedral drawing is as it was.
  if (result.has_smooth()) {
    std::snprintf(buf, sizeof buf, "  .outline { stroke: #000000; stroke-width: %gpx; }\n", style.outline_px);
    out += buf;
  }
  if (result.smooth_listed) {
    std::snprintf(buf, sizeof buf, "  .smooth { stroke: #9a9a9a; stroke-width: %gpx; }\n", style.smooth_px);
    out += buf;
  }
  out += "</style>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"" + colour(style.background) + "\"/>\n";
  const auto group = [&](const char* cls, const std::vector<HlrSegment>& segments, LineKind kind,
                         double px, const std::string& dash) {
    const std::string d = path(segments, to_pixels, {kind});
    std::snprintf(buf, sizeof buf,
                  "<g class=\"%s\" fill=\"none\" stroke-linecap=\"round\" stroke-linejoin=\"round\" "
                  "stroke-width=\"%g\"%s>\n",
                  cls, px, dash.c_str());
    out += buf;
    if (!d.empty()) out += "<path class=\"" + std::string(cls) + "\" d=\"" + d + "\"/>\n";
    out += "</g>\n";
  };
  if (style.hidden) {
    char dash[64];
    std::snprintf(dash, sizeof dash, " stroke-dasharray=\"%g %g\"", 4 * style.hidden_px, 3 * style.hidden_px);
    group("hidden", result.hidden, LineKind::Edge, style.hidden_px, dash);
  }
  group("visible", result.visible, LineKind::Edge, style.visible_px, "");
  if (result.smooth_listed) group("smooth", result.visible, LineKind::Smooth, style.smooth_px, "");
  group("junction", result.visible, LineKind::Junction, style.junction_px, "");
  if (result.has_smooth()) group("outline", result.visible, LineKind::Outline, style.outline_px, "");
  out += "</svg>\n";
  return out;
}

}  // namespace hedra
