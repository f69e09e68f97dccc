// The parts of the trajectory layout shared by the recorder and the writer (trajectory_layout.hpp).
#include "trajectory_layout.hpp"

#include <cmath>
#include <cstdint>

#include "dc/engine/trajectory_recorder.hpp"

namespace dc::trajectory {

void write_attributes(H5File& f, const std::string& scene, const std::string& warmstart) {
  f.set_attribute("/", "format", "deepcontact-trajectory");
  f.set_attribute<std::int32_t>("/", "format_version", kTrajectoryFormatVersion);
  f.set_attribute("/", "scene", scene);
  f.set_attribute("/", "warmstart", warmstart);
}

void write_body_tables(H5File& f, std::size_t n_bodies, const std::vector<double>& radius,
                       const std::vector<double>& mass, const ShapeTable& table) {
  ShapeTable shapes = table;
  if (shapes.empty()) shapes.add_circles(n_bodies);  // a circle-only scene: all kind 0, motion 0
  const hsize_t n = n_bodies;
  f.write<double>("/bodies/radius", radius, {n});
  f.write<double>("/bodies/mass", mass, {n});
  // Shape table (format_version 2): kind and motion per body, polygon vertices (body frame,
  // centroid at the origin) as rows [vertex_offset[k], vertex_offset[k+1]), ellipse semi-axes.
  std::vector<std::uint8_t> kind(n), motion(n);
  std::vector<double> verts, semi, pivot;
  for (std::size_t k = 0; k < n_bodies; ++k) {
    kind[k] = static_cast<std::uint8_t>(shapes.kind[k]);
    motion[k] = static_cast<std::uint8_t>(shapes.motion[k]);
    semi.push_back(shapes.semi_axes[k].x);
    semi.push_back(shapes.semi_axes[k].y);
    pivot.push_back(shapes.has_pivot[k] ? shapes.pivot[k].x : NAN);
    pivot.push_back(shapes.has_pivot[k] ? shapes.pivot[k].y : NAN);
  }
  for (const Vec2 v : shapes.vertices) {
    verts.push_back(v.x);
    verts.push_back(v.y);
  }
  const std::vector<std::int64_t> offsets(shapes.vertex_offset.begin(), shapes.vertex_offset.end());
  const hsize_t V = shapes.vertices.size();
  f.write<std::uint8_t>("/bodies/shape/kind", kind, {n});
  f.write<std::uint8_t>("/bodies/shape/motion", motion, {n});
  f.write<std::int64_t>("/bodies/shape/vertex_offset", offsets, {n + 1});
  f.write<double>("/bodies/shape/vertices", verts, {V, 2});
  f.write<double>("/bodies/shape/semi_axes", semi, {n, 2});
  f.write<double>("/bodies/shape/pivot", pivot, {n, 2});
}

}  // namespace dc::trajectory
