// The whole public API of hedra (kernel, io, render): #include <hedra/hedra.h> and link
// hedra::hedra. Baselines (hedra::baselines) and TetGen (hedra::tetgen, AGPL) are separate.
#pragma once

#include "hedra/version.h"

// core
#include "hedra/core/body.h"
#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/parallel.h"
#include "hedra/core/progress.h"
#include "hedra/core/plane.h"
#include "hedra/core/predicates.h"
#include "hedra/core/primitives.h"
#include "hedra/core/smooth_surface.h"
#include "hedra/core/tolerance.h"
#include "hedra/core/transform.h"

// mesh
#include "hedra/mesh/boolean.h"
#include "hedra/mesh/convexity.h"
#include "hedra/mesh/merge_coplanar.h"
#include "hedra/mesh/self_intersection.h"
#include "hedra/core/triangulate.h"

// decompose
#include "hedra/decompose/decompose.h"
#include "hedra/decompose/split.h"

// clip
#include "hedra/clip/batch_clip.h"
#include "hedra/clip/convex_clipper.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/clip/polygon_clip.h"
#include "hedra/clip/polyhedron_clipper.h"

// scene
#include "hedra/scene/camera.h"
#include "hedra/scene/demo.h"
#include "hedra/scene/light.h"
#include "hedra/scene/lod.h"
#include "hedra/scene/scene.h"
#include "hedra/scene/sun.h"

// visibility
#include "hedra/visibility/occlusion.h"
#include "hedra/visibility/outline.h"
#include "hedra/visibility/polygon_set.h"
#include "hedra/visibility/polygon_union.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"
#include "hedra/visibility/sun_study.h"

// io
#include "hedra/io/atomic_file.h"
#include "hedra/io/mesh_io.h"
#include "hedra/io/png.h"
#include "hedra/io/scene_json.h"
#include "hedra/io/text_reader.h"

// render
#include "hedra/render/raster.h"
#include "hedra/render/raster_view.h"
#include "hedra/render/ray_shadows.h"
#include "hedra/render/scene_geometry.h"
#include "hedra/render/shadow_map.h"
#include "hedra/render/svg.h"
