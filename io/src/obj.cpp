#include "obj.h"

#include <charconv>
#include <cstdio>

#include "hedra/io/text_reader.h"
#include "hedra/core/error.h"

namespace hedra::io {

PolygonSoup parse_obj(const std::string& path, const std::string& text) {
  TextReader in(path, text);
  PolygonSoup soup;
  struct Pending { std::vector<long long> ids; int line; };
  std::vector<Pending> faces;
  bool any = false;
  while (in.next_line()) {
    any = true;
    std::string_view kind = in.tokens()[0];
    if (kind == "v") {
      soup.vertices.emplace_back(in.number(1, "x"), in.number(2, "y"), in.number(3, "z"));
    } else if (kind == "f") {
      Pending face{{}, in.line_number()};
      for (size_t j = 1; j < in.tokens().size(); ++j) {
        std::string_view t = in.tokens()[j];
        t = t.substr(0, t.find('/'));
        long long id = 0;
        auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), id);
        if (ec != std::errc() || end != t.data() + t.size() || id == 0)
          in.fail("bad vertex reference '" + std::string(in.tokens()[j]) + "'");
        // Negative indices count back from the vertices read so far.
        face.ids.push_back(id > 0 ? id - 1 : static_cast<long long>(soup.vertices.size()) + id);
      }
      if (face.ids.size() < 3)
        in.fail("face has " + std::to_string(face.ids.size()) +
                " vertices; a face needs at least 3");
      faces.push_back(std::move(face));
    }
  }
  if (!any) throw InvalidInput(path + ": empty file");
  const long long nv = static_cast<long long>(soup.vertices.size());
  for (const Pending& f : faces) {
    std::vector<int> poly;
    for (long long id : f.ids) {
      if (id < 0 || id >= nv)
        throw InvalidInput(path + ":" + std::to_string(f.line) + ": vertex " +
                           std::to_string(id + 1) + " out of range (1.." + std::to_string(nv) +
                           ")");
      poly.push_back(static_cast<int>(id));
    }
    soup.polygons.push_back(std::move(poly));
  }
  if (soup.polygons.empty()) throw InvalidInput(path + ": no faces");
  return soup;
}

std::string format_obj(const PolygonSoup& soup,
                       const std::vector<std::pair<size_t, std::string>>& groups) {
  std::string out = "# written by hedra\n";
  char buf[96];
  for (const Vec3& p : soup.vertices) {
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    out += buf;
  }
  size_t group = 0;
  for (size_t f = 0; f < soup.polygons.size(); ++f) {
    const auto& poly = soup.polygons[f];
    for (; group < groups.size() && groups[group].first == f; ++group) {
      out += "o ";
      for (char c : groups[group].second)
        out += c == '\n' || c == '\r' || c == '#' || c == '\0' ? '_' : c;
      out += "\n";
    }
    out += "f";
    for (int v : poly) out += " " + std::to_string(v + 1);
    out += "\n";
  }
  return out;
}

}  // namespace hedra::io
