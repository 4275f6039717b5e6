// The tabulated cam profile: not implemented yet (the next commit).
#include "solve/cam/profiles.hpp"

namespace nvh::solve::cam {

std::unique_ptr<CamProfile> read_table_cam(const input::Table& t, const std::filesystem::path&,
                                           std::vector<std::filesystem::path>&) {
  t.fail("profile", "the table cam profile is not implemented yet");
}

}  // namespace nvh::solve::cam
