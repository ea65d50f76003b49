// OCCT's hidden lines as the benchmarks run them (hlr_bench on boxes, faces_bench on a slab, a
// sphere and a cylinder): box solids sewn from faces (Debian's OCCT 7.6 headers for BRepPrimAPI
// need a header the packages lack), the parallel projector of a hedra camera, the exact
// HLRBRep_Algo and the mesh-based HLRBRep_PolyAlgo, and the drawn 2D length of their visible
// sharp edges and outlines. Only with HEDRA_HAVE_OCCT.
#pragma once

#include <optional>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <HLRAlgo_Projector.hxx>
#include <HLRBRep_Algo.hxx>
#include <HLRBRep_HLRToShape.hxx>
#include <HLRBRep_PolyAlgo.hxx>
#include <HLRBRep_PolyHLRToShape.hxx>
#include <TopoDS.hxx>

#include "hedra/visibility/roberts.h"

namespace hedra::bench {

inline TopoDS_Shape occt_box(const Vec3& lo, const Vec3& hi) {
  gp_Pnt p[8];
  for (int i = 0; i < 8; ++i)
    p[i] = gp_Pnt(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  BRepBuilderAPI_Sewing sew;
  for (const auto& q : f) {
    BRepBuilderAPI_MakePolygon poly(p[q[0]], p[q[1]], p[q[2]], p[q[3]], Standard_True);
    sew.Add(BRepBuilderAPI_MakeFace(poly.Wire(), Standard_True).Face());
  }
  sew.Perform();
  return BRepBuilderAPI_MakeSolid(TopoDS::Shell(sew.SewedShape())).Solid();
}

inline double occt_length(const TopoDS_Shape& shape) {
  if (shape.IsNull()) return 0;
  GProp_GProps props;
  BRepGProp::LinearProperties(shape, props);
  return props.Mass();
}

/// Parallel only: the projection plane's normal points to the viewer, x along hedra's `right`.
inline HLRAlgo_Projector occt_projector(const Camera& camera) {
  const PictureProjection proj(camera);
  const Vec3 z = -proj.axis(), x = proj.right();
  return HLRAlgo_Projector(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(z.x(), z.y(), z.z()), gp_Dir(x.x(), x.y(), x.z())));
}

/// One run's results, kept so that a benchmark frees them outside its timed part (clear()).
struct OcctLines {
  Handle(HLRBRep_Algo) exact;
  Handle(HLRBRep_PolyAlgo) poly;
  std::optional<HLRBRep_PolyHLRToShape> poly_out;
  TopoDS_Shape visible, outline;

  void clear() {
    visible.Nullify();
    outline.Nullify();
    poly_out.reset();
    poly.Nullify();
    exact.Nullify();
  }
  /// Visible sharp edges and outlines, in the picture plane.
  double length() const { return occt_length(visible) + occt_length(outline); }
};

/// The exact HLRBRep_Algo on `shape` (analytic or polyhedral). `out` must be clear().
inline void occt_exact_lines(const TopoDS_Shape& shape, const Camera& camera, OcctLines& out) {
  out.exact = new HLRBRep_Algo();
  out.exact->Add(shape);
  out.exact->Projector(occt_projector(camera));
  out.exact->Update();
  out.exact->Hide();
  HLRBRep_HLRToShape shapes(out.exact);
  out.visible = shapes.VCompound();
  out.outline = shapes.OutLineVCompound();
}

/// HLRBRep_PolyAlgo on `shape`, which must be meshed already. `out` must be clear().
inline void occt_poly_lines(const TopoDS_Shape& shape, const Camera& camera, OcctLines& out) {
  out.poly = new HLRBRep_PolyAlgo(shape);
  out.poly->Projector(occt_projector(camera));
  out.poly->Update();
  out.poly_out.emplace();
  out.poly_out->Update(out.poly);
  out.visible = out.poly_out->VCompound();
  out.outline = out.poly_out->OutLineVCompound();
}

}  // namespace hedra::bench
