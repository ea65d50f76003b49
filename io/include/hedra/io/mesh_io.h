// Reading and writing meshes (OFF, OBJ, STL, PLY), chosen by file extension.
//
// hedra parses and writes these formats itself rather than through OpenMesh: OpenMesh 9's
// readers and writers store coordinates as 32-bit floats, which would break exact round trips
// and exact planarity of imported faces, and they do not report where a file is malformed.
// OpenMesh reads every file hedra writes (checked in tests/io/mesh_io_test.cpp).
#pragma once

#include <string>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/mesh/merge_coplanar.h"

namespace hedra::io {

enum class MeshFormat { Off, Obj, Stl, Ply };

/// Format from the extension (case-insensitive .off .obj .stl .ply).
/// \throw InvalidInput for any other extension.
MeshFormat format_of(const std::string& path);

struct ReadOptions {
  MergeOptions merge;  // coplanar tolerance, planarity tolerance
};

/// Polygons as stored in the file. \throw IoError, InvalidInput ("file:line: …").
PolygonSoup read_soup(const std::string& path);

/// Bodies of a mesh file: coplanar neighbours merged into polygonal faces, one body per
/// connected component, validated. Every message starts with the file name.
std::vector<Body> read_bodies(const std::string& path, const ReadOptions& options = {});

struct WriteOptions {
  bool stl_ascii = false;  // binary STL (float32) by default
  /// Body names, one per body (or none): OBJ writes each body as an "o name" group.
  std::vector<std::string> names;
};

/// The bodies as one polygon soup: faces without holes as polygons; faces with holes (which
/// these formats cannot store) as their triangles, or everything as triangles when
/// `triangles_only`. Reading the result back merges the triangles into the same faces.
PolygonSoup soup_of(const std::vector<Body>& bodies, bool triangles_only);

/// The bytes write_bodies() writes in `format`.
std::string format_bodies(const std::vector<Body>& bodies, MeshFormat format,
                          const WriteOptions& options = {});

/// Writes the bodies to `path` in the format of its extension, atomically.
/// \throw IoError, InvalidInput (unknown extension).
void write_bodies(const std::vector<Body>& bodies, const std::string& path,
                  const WriteOptions& options = {});

}  // namespace hedra::io
