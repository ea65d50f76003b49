#include "hedra/tetgen/tetgen_decompose.h"

#include <cmath>
#include <string>

#define TETLIBRARY
#include <tetgen.h>

#include <string>

#include "hedra/core/error.h"

namespace hedra::tetgen {

Decomposition decompose(const Body& body) {
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = body.vertex_count();
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (int i = 0; i < body.vertex_count(); ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = body.vertices()[i][k];
  // One facet per triangle of the faces' triangulations (faces with holes need no hole points).
  const auto& triangles = body.triangles();
  in.numberoffacets = static_cast<int>(triangles.size());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  for (size_t t = 0; t < triangles.size(); ++t) {
    tetgenio::facet& f = in.facetlist[t];
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = 3;
    f.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) f.polygonlist[0].vertexlist[k] = triangles[t].v[k];
  }
  char switches[] = "pQ";
  try {
    tetrahedralize(switches, &in, &out);
  } catch (int code) {
    throw InvalidInput("TetGen rejected the body (error " + std::to_string(code) + ")");
  }
  Decomposition result;
  auto point = [&](int i) {
    return Vec3(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
  };
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    std::vector<Vec3> v;
    for (int k = 0; k < 4; ++k) v.push_back(point(out.tetrahedronlist[4 * t + k]));
    // Faces counter-clockwise from outside for a positively oriented tetrahedron.
    const bool positive = (v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0])) > 0;
    if (!positive) std::swap(v[2], v[3]);
    result.pieces.emplace_back(v, std::vector<Face>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
  }
  // TetGen can give up quietly (no tetrahedra, e.g. a very thin rotated body): say so.
  double volume = 0;
  for (const Body& piece : result.pieces) volume += piece.volume();
  if (result.pieces.empty() || std::abs(volume - body.volume()) > 1e-9 * body.volume())
    throw InvalidInput("TetGen's " + std::to_string(result.pieces.size()) +
                       " tetrahedra do not fill the body (volume " + std::to_string(volume) +
                       " of " + std::to_string(body.volume()) + ")");
  return result;
}

}  // namespace hedra::tetgen
