#pragma once
// Private to the trajectory recorder and writer: the parts of the trajectory layout
// (docs/formats.md "Trajectory") that both write the same way.
#include <string>
#include <vector>

#include "dc/engine/shape.hpp"
#include "dc/io/h5.hpp"

namespace dc::trajectory {

/// Root attributes: format, format_version, scene (TOML), warmstart.
void write_attributes(H5File& f, const std::string& scene, const std::string& warmstart);

/// /bodies/radius, /bodies/mass and the shape table /bodies/shape/* of n bodies (an empty
/// table: n circles).
void write_body_tables(H5File& f, std::size_t n, const std::vector<double>& radius, const std::vector<double>& mass,
                       const ShapeTable& shapes);

}  // namespace dc::trajectory
