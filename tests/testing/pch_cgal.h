// The precompiled header of the tests that include CGAL (directly or through
// testing/clip_fixtures.h): testing/pch.h and CGAL's kernels, whose parsing alone is about 12 s
// of each such test's compilation with GCC -O3. Kept apart from testing/pch.h because loading
// it (about 650 MB with GCC) costs the other tests more than it saves them.
#include "testing/pch.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
