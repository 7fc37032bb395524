// The overlap the surface contact ignores after its surface changed under a slave
// (solver/coupling/ignored_overlap.hpp): motion is never ignored, a jump of the surface is —
// less the slave's own motion in that step — and what is ignored only shrinks, never beyond the
// overlap.
#include "solver/coupling/ignored_overlap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sphfem;

namespace {
const double unknown = std::numeric_limits<double>::quiet_NaN(); // no s before: new
const double moved = 1e-5; // the most the bodies' motion moves s in a step, m
} // namespace

TEST(IgnoredOverlap, MotionIsNeverIgnored) {
  // A slave closing on the surface and pressing 4 µm into it, step by step.
  double ignored = 0;
  for (double s = 2e-5, previous = 2.8e-5; s > -4e-6; previous = s, s -= 8e-6) {
    ignored = ignored_overlap(previous, s, s, moved, -s, ignored);
    EXPECT_EQ(ignored, 0.0) << "s = " << s;
  }
}

TEST(IgnoredOverlap, AJumpOfTheSurfaceIsIgnoredLessTheSlavesOwnMotion) {
  // Pressed 2 µm in, then the surface jumps 300 µm further in while the slave moved 1 µm out:
  // the force goes on from 1 µm of overlap, the motion's part.
  const double previous = -2e-6, expected = previous + 1e-6, s = expected - 3e-4;
  const double ignored = ignored_overlap(previous, expected, s, moved, -s, 0.0);
  EXPECT_NEAR(ignored, 3e-4, 1e-15);
  EXPECT_NEAR(-s - ignored, 1e-6, 1e-15); // the overlap that pushes
  // A slave new to the surface: its whole overlap is ignored.
  EXPECT_EQ(ignored_overlap(unknown, unknown, -5e-5, moved, 5e-5, 0.0), 5e-5);
}

TEST(IgnoredOverlap, WhatIsIgnoredOnlyShrinksAndNeverPulls) {
  double ignored = 3e-4, s = -3.01e-4;
  // Pressed further in by motion: the ignored part stays, the pushing overlap grows.
  ignored = ignored_overlap(s, s - 5e-6, s - 5e-6, moved, -(s - 5e-6), ignored);
  s -= 5e-6;
  EXPECT_EQ(ignored, 3e-4);
  // Coming out beyond it: the ignored part follows the overlap down, never above it.
  for (int k = 0; k < 40; ++k) {
    const double next = s + 9e-6;
    ignored = ignored_overlap(s, next, next, moved, -next, ignored);
    s = next;
    EXPECT_LE(ignored, std::max(-s, 0.0));
  }
  EXPECT_GT(s, 0.0);
  EXPECT_EQ(ignored, 0.0);
  // A jump out of the body is not ignored the other way: nothing to ignore.
  EXPECT_EQ(ignored_overlap(-1e-4, -1e-4, 2e-4, moved, -2e-4, 5e-5), 0.0);
}
