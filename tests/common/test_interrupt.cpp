// SIGTERM / SIGINT handling (common/interrupt.hpp), each case in a child process (GoogleTest's EXPECT_EXIT
// forks), since the handler state is process-wide. Reference: the documented behaviour - exit code 3
// (ExitCode::kInterrupted) outside graceful mode; in graceful mode a flag, and a repeat within 2 s is the same
// request (GNU timeout delivers its signal twice: to the child, then to its process group).
#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <cstdlib>

#include "common/interrupt.hpp"

namespace nvh {
namespace {

TEST(Interrupt, OutsideGracefulModeASignalExitsWithCode3) {
  EXPECT_EXIT(
      {
        install_interrupt_handler("test");
        std::raise(SIGTERM);
        std::_Exit(0);
      },
      ::testing::ExitedWithCode(3), "terminated \\(SIGTERM\\)");
}

TEST(Interrupt, InGracefulModeTheSameRequestDeliveredTwiceIsOneRequest) {
  EXPECT_EXIT(
      {
        install_interrupt_handler("test");
        set_graceful_interrupt(true);
        std::raise(SIGTERM);
        std::raise(SIGTERM);  // as GNU timeout does, microseconds later
        std::_Exit(interrupt_requested() && interrupt_signal() == SIGTERM ? 7 : 8);
      },
      ::testing::ExitedWithCode(7), "");
}

TEST(Interrupt, InGracefulModeASecondSignalLaterForcesTheExit) {
  EXPECT_EXIT(
      {
        install_interrupt_handler("test");
        set_graceful_interrupt(true);
        std::raise(SIGINT);
        ::usleep(2'200'000);  // beyond the 2 s window
        std::raise(SIGINT);
        std::_Exit(0);
      },
      ::testing::ExitedWithCode(3), "interrupted \\(SIGINT\\)");
}

}  // namespace
}  // namespace nvh
