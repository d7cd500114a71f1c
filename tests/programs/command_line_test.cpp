// The programs' shared command-line pieces: the progress bar's text and the names of the images
// of an animation.
#include <string>

#include <catch2/catch.hpp>

#include "common/progress_bar.hpp"
#include "common/render_options.hpp"

using igi::programs::FrameNames;
using igi::programs::progress_line;
using igi::programs::UsageError;

TEST_CASE("the progress bar fills in proportion and estimates the time left from the rate so far", "[programs]") {
  // 3 of 12 done in 1.5 s: a quarter of 8 characters filled, 0.5 s per unit, 9 left.
  CHECK(progress_line(3, 12, 1.5, 8, "frames") == "[==>     ] 3/12 frames  25%  eta 4.5 s");
  // Nothing done yet: no rate, so no estimate; the head of the bar sits at the start.
  CHECK(progress_line(0, 12, 0.0, 8, "frames") == "[>       ] 0/12 frames   0%");
  // Done: a full bar, 100% and no estimate; more than the total is clamped to it.
  CHECK(progress_line(12, 12, 9.0, 8, "spp") == "[========] 12/12 spp 100%");
  CHECK(progress_line(15, 12, 9.0, 8, "spp") == "[========] 12/12 spp 100%");
}

TEST_CASE("animation frames are numbered before the extension or where the pattern says", "[programs]") {
  const FrameNames plain("renders/out.png", 3);
  CHECK(plain(0).string() == "renders/out_0000.png");
  CHECK(plain(2).string() == "renders/out_0002.png");
  // More frames than four digits hold: as many digits as the last frame needs, so names sort.
  CHECK(FrameNames("out.exr", 12001)(7).string() == "out_00007.exr");
  CHECK(FrameNames("frames/%04d.png", 3)(7).string() == "frames/0007.png");
  CHECK(FrameNames("f%d.pfm", 3)(12).string() == "f12.pfm");
  CHECK(FrameNames("100%%_%03d.png", 3)(5).string() == "100%_005.png");
}

TEST_CASE("malformed frame-number patterns are usage errors that say how to write one", "[programs]") {
  CHECK_THROWS_AS(FrameNames("x%5d.png", 2), UsageError);
  CHECK_THROWS_WITH(FrameNames("x%s.png", 2), Catch::Contains("%0Nd"));
  CHECK_THROWS_WITH(FrameNames("%d_%d.png", 2), Catch::Contains("more than one frame number"));
  CHECK_THROWS_AS(FrameNames("x%", 2), UsageError);
}
