// The polynomial cam profile: not implemented yet (the next commit).
#include "solve/cam/profiles.hpp"

namespace nvh::solve::cam {

std::unique_ptr<CamProfile> read_polynomial_cam(const input::Table& t) {
  t.fail("profile", "the polynomial cam profile is not implemented yet");
}

}  // namespace nvh::solve::cam
