#include "off.h"

#include <cstdio>

#include "hedra/io/text_reader.h"
#include "hedra/core/error.h"

namespace hedra::io {

PolygonSoup parse_off(const std::string& path, const std::string& text) {
  TextReader in(path, text);
  if (!in.next_line()) in.fail("empty file (expected an OFF header)");
  std::string_view header = in.tokens()[0];
  const bool known = header == "OFF" || header == "COFF" || header == "NOFF" ||
                     header == "CNOFF" || header == "STOFF";
  if (!known) in.fail("not an OFF file: first word is '" + std::string(header) + "'");
  size_t counts_at = 1;
  if (in.tokens().size() == 1) {
    if (!in.next_line()) in.fail("missing vertex and face counts");
    counts_at = 0;
  }
  const long long nv = in.integer(counts_at, "vertex count");
  const long long nf = in.integer(counts_at + 1, "face count");
  if (nv < 0 || nf < 0 || nv > 100'000'000 || nf > 100'000'000)
    in.fail("implausible counts " + std::to_string(nv) + " vertices, " + std::to_string(nf) +
            " faces");
  // A vertex takes at least 5 bytes ("0 0 0"), a face at least 7 ("3 0 1 2"): counts that
  // the file cannot hold are rejected before anything is reserved for them.
  if (5 * nv + 7 * nf > static_cast<long long>(text.size()))
    in.fail("the header's counts (" + std::to_string(nv) + " vertices, " + std::to_string(nf) +
            " faces) need more than the file's " + std::to_string(text.size()) + " bytes");
  PolygonSoup soup;
  soup.vertices.reserve(nv);
  for (long long i = 0; i < nv; ++i) {
    if (!in.next_line())
      in.fail("unexpected end of file: read " + std::to_string(i) + " of " + std::to_string(nv) +
              " vertices");
    soup.vertices.emplace_back(in.number(0, "x"), in.number(1, "y"), in.number(2, "z"));
  }
  soup.polygons.reserve(nf);
  for (long long f = 0; f < nf; ++f) {
    if (!in.next_line())
      in.fail("unexpected end of file: read " + std::to_string(f) + " of " + std::to_string(nf) +
              " faces");
    const long long k = in.integer(0, "face size");
    if (k < 3)
      in.fail("face " + std::to_string(f) + " has " + std::to_string(k) +
              " vertices; a face needs at least 3");
    if (static_cast<long long>(in.tokens().size()) < k + 1)
      in.fail("face " + std::to_string(f) + " lists fewer than its " + std::to_string(k) +
              " vertex indices");
    std::vector<int> poly;
    poly.reserve(static_cast<size_t>(k));
    for (long long j = 1; j <= k; ++j) {
      long long id = in.integer(j, "vertex index");
      if (id < 0 || id >= nv)
        in.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(id) +
                ", out of range (0.." + std::to_string(nv - 1) + ")");
      poly.push_back(static_cast<int>(id));
    }
    soup.polygons.push_back(std::move(poly));
  }
  return soup;
}

std::string format_off(const PolygonSoup& soup) {
  std::string out = "OFF\n" + std::to_string(soup.vertices.size()) + " " +
                    std::to_string(soup.polygons.size()) + " 0\n";
  char buf[96];
  for (const Vec3& p : soup.vertices) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    out += buf;
  }
  for (const auto& poly : soup.polygons) {
    out += std::to_string(poly.size());
    for (int v : poly) out += " " + std::to_string(v);
    out += "\n";
  }
  return out;
}

}  // namespace hedra::io
