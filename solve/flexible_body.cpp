#include "solve/flexible_body.hpp"

namespace nvh::solve {

std::unique_ptr<Body> make_flexible_body(const input::Table& t, const std::string&, const InitialState&,
                                         const std::filesystem::path&, std::vector<std::filesystem::path>&) {
  t.fail("type", "flexible bodies are not available in this build of solve yet");
}

}  // namespace nvh::solve
