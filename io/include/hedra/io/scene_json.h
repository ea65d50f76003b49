// The JSON scene file, version 1 (docs/scene-format.md).
#pragma once

#include <string>

#include "hedra/scene/scene.h"

namespace hedra::io {

/// Reads a scene file. Mesh paths are relative to the scene file's directory.
/// \throw InvalidInput "scene.json:14:9: body 'L': 'polygon' needs at least 3 points" (file,
///   line, column, context, problem); unknown keys are errors. IoError if unreadable.
/// `tolerance` > 0: meshes are imported with that coplanar tolerance (the command's
/// `--tolerance`, see MergeOptions), overriding the file's top-level "tolerance" key.
Scene read_scene(const std::string& path, double tolerance = 0);
/// The same from text; `path` names the file in messages and anchors relative mesh paths.
Scene parse_scene(const std::string& path, const std::string& text, double tolerance = 0);

/// The scene as JSON text: every body as an explicit "polyhedron" (exact coordinates, faces
/// with holes as lists of loops), so reading it back gives an equivalent scene.
std::string format_scene(const Scene& scene);
/// Writes format_scene atomically. \throw IoError.
void write_scene(const Scene& scene, const std::string& path);

/// True for a ".json" file name.
bool is_scene_path(const std::string& path);

}  // namespace hedra::io
