// Logger prefixes and Progress output in batch-log form (lines), on a string stream.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "common/progress.hpp"

namespace nvh {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool starts_with(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}
bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Logger, PrefixesAndVerbosity) {
  std::ostringstream out;
  const Logger normal(out, "condense");
  normal.info("reading crank.toml");
  normal.detail("not shown");
  normal.warning("mesh is coarse");
  normal.error("no modes");
  EXPECT_EQ(out.str(),
            "[condense] reading crank.toml\n"
            "[condense] warning: mesh is coarse\n"
            "[condense] error: no modes\n");

  std::ostringstream quiet_out;
  const Logger quiet(quiet_out, "solve", Verbosity::kQuiet);
  quiet.info("hidden");
  quiet.detail("hidden");
  quiet.warning("shown");
  EXPECT_EQ(quiet_out.str(), "[solve] warning: shown\n");

  std::ostringstream verbose_out;
  const Logger verbose(verbose_out, "solve", Verbosity::kVerbose);
  verbose.detail("step 3");
  EXPECT_EQ(verbose_out.str(), "[solve] step 3\n");
  EXPECT_EQ(verbose.verbosity(), Verbosity::kVerbose);
  EXPECT_EQ(verbose.tool(), "solve");
  EXPECT_EQ(&verbose.stream(), &verbose_out);
}

TEST(Progress, LinesWithPercentagesAndFinalDone) {
  std::ostringstream out;
  const Logger logger(out, "solve");
  {
    Progress progress(logger, "eigen-solve", 1000, Progress::Style::kLines, std::chrono::seconds(0));
    EXPECT_EQ(progress.style(), Progress::Style::kLines);
    for (int done = 0; done <= 1000; done += 250) progress.update(done);
    progress.finish();
    progress.finish();  // a second finish() prints nothing more
  }
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 6u) << out.str();
  EXPECT_TRUE(starts_with(lines[0], "[solve] eigen-solve: 0% (0/1000), ")) << lines[0];
  EXPECT_TRUE(starts_with(lines[1], "[solve] eigen-solve: 25% (250/1000), ")) << lines[1];
  EXPECT_TRUE(contains(lines[1], " s elapsed, ~")) << lines[1];
  EXPECT_TRUE(contains(lines[1], " left")) << lines[1];
  EXPECT_TRUE(starts_with(lines[2], "[solve] eigen-solve: 50% (500/1000), ")) << lines[2];
  EXPECT_TRUE(starts_with(lines[3], "[solve] eigen-solve: 75% (750/1000), ")) << lines[3];
  EXPECT_TRUE(starts_with(lines[4], "[solve] eigen-solve: 100% (1000/1000), ")) << lines[4];
  EXPECT_TRUE(starts_with(lines[5], "[solve] eigen-solve: done in ")) << lines[5];
  EXPECT_TRUE(lines[5].size() > 2 && lines[5].substr(lines[5].size() - 2) == " s") << lines[5];
}

TEST(Progress, ZeroIntervalPrintsOncePerPercentage) {
  std::ostringstream out;
  const Logger logger(out, "solve");
  Progress progress(logger, "assembly", 10000, Progress::Style::kLines, std::chrono::seconds(0));
  for (int done = 0; done <= 300; ++done) progress.update(done);  // 0%, 1%, 2%, 3%
  progress.finish();
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 5u) << out.str();
  EXPECT_TRUE(contains(lines[3], ": 3% (300/10000)")) << lines[3];
}

TEST(Progress, LongIntervalPrintsOnlyTheFinalLine) {
  std::ostringstream out;
  const Logger logger(out, "condense");
  {
    Progress progress(logger, "modes", 50, Progress::Style::kAuto, std::chrono::seconds(3600));
    EXPECT_EQ(progress.style(), Progress::Style::kLines);  // a string stream is no terminal
    for (int done = 0; done <= 50; ++done) progress.update(done);
  }  // the destructor finishes
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 1u) << out.str();
  EXPECT_TRUE(starts_with(lines[0], "[condense] modes: done in ")) << lines[0];
}

TEST(Progress, NoneAndQuietPrintNothing) {
  std::ostringstream out;
  const Logger logger(out, "solve");
  {
    Progress progress(logger, "silent", 10, Progress::Style::kNone, std::chrono::seconds(0));
    for (int done = 0; done <= 10; ++done) progress.update(done);
    progress.finish();
  }
  EXPECT_EQ(out.str(), "");

  std::ostringstream quiet_out;
  const Logger quiet(quiet_out, "solve", Verbosity::kQuiet);
  for (const auto style : {Progress::Style::kAuto, Progress::Style::kLines, Progress::Style::kBar}) {
    Progress progress(quiet, "quiet", 10, style, std::chrono::seconds(0));
    EXPECT_EQ(progress.style(), Progress::Style::kNone);
    for (int done = 0; done <= 10; ++done) progress.update(done);
    progress.finish();
  }
  EXPECT_EQ(quiet_out.str(), "");
}

TEST(Progress, BarIsRedrawnInPlaceAndEndsWithDone) {
  std::ostringstream out;
  const Logger logger(out, "solve");
  Progress progress(logger, "time-step", 100, Progress::Style::kBar);
  progress.update(45);
  progress.finish();
  const std::string text = out.str();
  EXPECT_TRUE(starts_with(text, "\r[time-step] [#############.................]  45%  ")) << text;
  EXPECT_TRUE(contains(text, "[solve] time-step: done in ")) << text;
  EXPECT_EQ(text.back(), '\n');
}

TEST(Progress, UnknownTotalCountsSteps) {
  std::ostringstream out;
  const Logger logger(out, "solve");
  Progress progress(logger, "iterations", 0, Progress::Style::kLines, std::chrono::seconds(0));
  progress.update(7);
  progress.finish();
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 2u) << out.str();
  EXPECT_TRUE(starts_with(lines[0], "[solve] iterations: 7 done, ")) << lines[0];
}

}  // namespace
}  // namespace nvh
