// libhdf5's exit-time cleanup (h5.hpp: h5_skip_exit_cleanup).
#include "dc/io/h5.hpp"
#include "h5_detail.hpp"

namespace dc {

bool h5_skip_exit_cleanup() { return H5dont_atexit() >= 0; }

}  // namespace dc
