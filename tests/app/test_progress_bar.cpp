// The progress bar of `nmdp simulate` (src/app/progress_bar.*): silent when not on a terminal or
// disabled, shows steps / simulated time / real-time factor, ends its line on finish(), and redraws
// at most every ProgressBar::kMinRedrawInterval of wall time however often it is updated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "app/progress_bar.hpp"

namespace nmdp::app {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openTemporary() {
  File f(std::tmpfile());
  if (!f) throw std::runtime_error("tmpfile() failed");
  return f;
}

std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string out;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) out.append(buffer, n);
  return out;
}

TEST(ProgressBar, IsNotShownOnAFileOrWhenQuiet) {
  File f = openTemporary();
  EXPECT_FALSE(ProgressBar::shouldShow(f.get(), false));
  EXPECT_FALSE(ProgressBar::shouldShow(f.get(), true));
  EXPECT_FALSE(ProgressBar::shouldShow(nullptr, false));
}

TEST(ProgressBar, ShowsStepsTimeAndRealTimeFactorAndEndsTheLine) {
  File f = openTemporary();
  {
    ProgressBar bar(f.get(), 10.0, true);
    bar.update(1, 0.01, 0.001);
    bar.update(1234, 4.5, 2.0);  // more than kMinRedrawInterval later: redrawn
    bar.finish();
    bar.finish();  // idempotent
  }
  const std::string out = contents(f.get());
  EXPECT_NE(out.find("step 1234"), std::string::npos) << out;
  EXPECT_NE(out.find("4.50 / 10.00 s"), std::string::npos) << out;
  EXPECT_NE(out.find("2.25x real time"), std::string::npos) << out;
  EXPECT_NE(out.find(" 45%"), std::string::npos) << out;
  EXPECT_EQ(out.front(), '\r');
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.back(), '\n');
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << "one line, redrawn in place";
}

TEST(ProgressBar, FinishDrawsTheLastStateEvenBetweenRedraws) {
  File f = openTemporary();
  ProgressBar bar(f.get(), 2.0, true);
  bar.update(1, 0.01, 0.0);
  bar.update(200, 2.0, 0.05);  // too soon to redraw
  bar.finish();
  const std::string out = contents(f.get());
  const std::string last = out.substr(out.rfind('\r'));
  EXPECT_NE(last.find("step 200"), std::string::npos) << out;
  EXPECT_NE(last.find("100%"), std::string::npos) << out;
  EXPECT_NE(last.find("40.00x real time"), std::string::npos) << out;
}

TEST(ProgressBar, RedrawsAtMostTenTimesPerSecondOfWallTime) {
  File f = openTemporary();
  ProgressBar bar(f.get(), 100.0, true);
  const int updates = 100000;
  const double wall_span = 0.35;  // s: room for the first draw and three more
  for (int i = 1; i <= updates; ++i) bar.update(i, i * 1e-3, wall_span * i / updates);
  const std::string out = contents(f.get());
  const auto redraws = std::count(out.begin(), out.end(), '\r');
  EXPECT_GE(redraws, 3);
  EXPECT_LE(redraws, 1 + static_cast<long>(wall_span / ProgressBar::kMinRedrawInterval));
}

TEST(ProgressBar, ShorterLineBlanksTheRestOfTheLongerOne) {
  File f = openTemporary();
  ProgressBar bar(f.get(), 1.0, true);
  bar.update(123456789, 0.5, 0.1);
  bar.update(1, 0.5, 0.3);
  const std::string out = contents(f.get());
  const size_t second = out.rfind('\r');
  EXPECT_EQ(out.size() - second, second) << "the second line is padded to the first one's width:\n" << out;
}

TEST(ProgressBar, DisabledWritesNothing) {
  File f = openTemporary();
  {
    ProgressBar bar(f.get(), 10.0, false);
    for (int i = 0; i < 100; ++i) bar.update(i, i * 0.1, i * 1.0);
    bar.finish();
  }
  EXPECT_TRUE(contents(f.get()).empty());
}

TEST(ProgressBar, ZeroDurationAndZeroWallTimeAreShownWithoutDividingByZero) {
  File f = openTemporary();
  ProgressBar bar(f.get(), 0.0, true);
  bar.update(0, 0.0, 0.0);
  bar.finish();
  const std::string out = contents(f.get());
  EXPECT_NE(out.find("--x real time"), std::string::npos) << out;
  EXPECT_NE(out.find("  0%"), std::string::npos) << out;
  EXPECT_EQ(out.find("nan"), std::string::npos) << out;
  EXPECT_EQ(out.find("inf"), std::string::npos) << out;
}

TEST(ProgressBar, DestructorEndsAnUnfinishedLine) {
  File f = openTemporary();
  { ProgressBar(f.get(), 1.0, true).update(3, 0.1, 0.2); }
  const std::string out = contents(f.get());
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.back(), '\n');
}

}  // namespace
}  // namespace nmdp::app
