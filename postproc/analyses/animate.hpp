#pragma once
// postproc animate: a flexible body's deformed surface over a time window as XDMF 3 + HDF5 for ParaView
// (docs/postproc.md section 3.6): the superelement's exported surface as the mesh, and per frame the
// displacement (modal superposition of the modal coordinates, eq. (1) of postproc/surface_motion.hpp; with
// the frame's rigid-body motion, eq. (2)) and the normal velocity (eq. (1) and (1a) of
// postproc/surface_radiation.hpp) as node fields.
#include <filesystem>
#include <optional>
#include <string>

#include "common/log.hpp"

namespace nvh::postproc {

struct AnimateCommand {
  std::filesystem::path results;           ///< solve's results file
  std::filesystem::path superelement;      ///< the body's superelement file (with /surface)
  std::string body;                        ///< the flexible body's name in the results (/bodies/<body>)
  std::filesystem::path output;            ///< OUT.xdmf; the data go to OUT.h5 beside it
  std::optional<double> from_s, to_s;      ///< time window, s (default: the whole run)
  std::optional<double> from_deg, to_deg;  ///< or a crank-angle window, deg of /crank_angle_deg
  std::int64_t max_frames = 200;           ///< at most this many frames, evenly spaced samples
  bool include_rigid = false;              ///< add the frame's rigid-body motion (global axes)
  double scale = 1.0;                      ///< displacement scale recorded for Warp By Vector
  bool displaced_geometry = false;         ///< also write x + scale d per frame as the geometry
};

/// Writes `output` and the HDF5 file beside it (temporaries, renamed when complete); an error leaves neither.
void run_animate(const AnimateCommand& command, const Logger& log, int argc, const char* const* argv);

/// The HDF5 file an animation writes beside `xdmf` (its extension replaced by .h5).
std::filesystem::path animation_data_path(const std::filesystem::path& xdmf);

}  // namespace nvh::postproc
