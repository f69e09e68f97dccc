// libccd glue (shape_collide.hpp): 2D shapes as prisms of half-height H in 3D, inflated by δ.
#include <ccd/ccd.h>

#include <cmath>

#include "dc/engine/shape_collide.hpp"

namespace dc {
namespace {

struct CcdShape {
  const ShapePose* pose;
  double inflate;      ///< δ [m]
  double half_height;  ///< H [m]
  double z0;           ///< middle of the prism along z [m]
};

void support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const auto* o = static_cast<const CcdShape*>(obj);
  const Vec2 d{dir->v[0], dir->v[1]};
  const double l = length(d);
  Vec2 p = o->pose->x;  // a pure ±z direction: any point of the end face
  if (l > 1e-300) p = o->pose->support(d) + (o->inflate / l) * d;
  out->v[0] = p.x;
  out->v[1] = p.y;
  out->v[2] = o->z0 + (dir->v[2] >= 0 ? o->half_height : -o->half_height);
}

void center(const void* obj, ccd_vec3_t* out) {
  const auto* o = static_cast<const CcdShape*>(obj);
  out->v[0] = o->pose->x.x;
  out->v[1] = o->pose->x.y;
  out->v[2] = o->z0;
}

void first_dir(const void* o1, const void* o2, ccd_vec3_t* dir) {
  const Vec2 d = static_cast<const CcdShape*>(o2)->pose->x - static_cast<const CcdShape*>(o1)->pose->x;
  dir->v[0] = d.x;
  dir->v[1] = d.y;
  dir->v[2] = 0;
  if (d.x == 0 && d.y == 0) dir->v[0] = 1;
}

}  // namespace

bool ccd_normal_gap(const ShapePose& a, const ShapePose& b, double inflate_a, double inflate_b, CcdMethod method,
                    Vec2& normal, double& gap) {
  // H above any in-plane depth (≤ r_a + r_b + δ_a + δ_b): the z faces never give the minimum.
  // b's prism is shifted along z by 0.37 H: with two prisms symmetric about z = 0, every support
  // point of A − B in an in-plane direction has z = 0 exactly, the simplices are flat and GJK
  // reports a touching contact (depth 0) for overlapping pairs.
  const double H = 2 * (a.radius + b.radius + inflate_a + inflate_b) + 1e-9;
  const CcdShape sa{&a, inflate_a, H, 0.0}, sb{&b, inflate_b, H, 0.37 * H};
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = support;
  ccd.support2 = support;
  ccd.center1 = center;
  ccd.center2 = center;
  ccd.first_dir = first_dir;
  ccd.max_iterations = 100;
  const double scale = a.radius + b.radius;
  ccd.epa_tolerance = 1e-9 * scale;
  ccd.mpr_tolerance = 1e-9 * scale;
  ccd.dist_tolerance = 1e-12 * scale;
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  int rc = method == CcdMethod::Mpr ? ccdMPRPenetration(&sa, &sb, &ccd, &depth, &dir, &pos)
                                    : ccdGJKPenetration(&sa, &sb, &ccd, &depth, &dir, &pos);
  if (rc != 0) return false;
  // GJK ends on a flat simplex (the origin on one of its edges) for nearly aligned faces and
  // then reports a "touching" contact: depth 0 and an arbitrary direction although the inflated
  // shapes overlap by up to δ_a + δ_b. MPR does not have this case: ask it instead.
  if (method == CcdMethod::GjkEpa && !(depth > 1e-9 * scale)) {
    rc = ccdMPRPenetration(&sa, &sb, &ccd, &depth, &dir, &pos);
    if (rc != 0) return false;
  }
  const Vec2 d{dir.v[0], dir.v[1]};
  const double l = length(d);
  if (!(l > 1e-12) || !std::isfinite(depth)) {
    // Touching exactly at the inflated boundary (depth 0, no direction): along the centres.
    const Vec2 c = b.x - a.x;
    const double lc = length(c);
    normal = lc > 0 ? (1.0 / lc) * c : Vec2{0.0, 1.0};
  } else {
    normal = (1.0 / l) * d;
  }
  gap = inflate_a + inflate_b - depth;
  return true;
}

}  // namespace dc
