#include <gtest/gtest.h>

#include "ohm_mirror_detector3d/ros/problem_throttle.h"

namespace
{
using ohm_mirror_detector3d::ros_io::ProblemThrottle;

TEST(ProblemThrottle, NumbersDoNotMakeANewKindOfProblem)
{
  EXPECT_EQ(ProblemThrottle::kindOf("data holds 12 bytes but height * row_step = 400"),
            "data holds # bytes but height * row_step = #");
  EXPECT_EQ(ProblemThrottle::kindOf("data holds 12 bytes"), ProblemThrottle::kindOf("data holds 4096 bytes"));
}

TEST(ProblemThrottle, EachKindAndTopicOncePerPeriodWithACountOfTheRest)
{
  ProblemThrottle throttle(5.0);
  std::size_t suppressed = 99;
  EXPECT_TRUE(throttle.shouldReport("/a", "has no 'x' field", 100.0, suppressed));
  EXPECT_EQ(suppressed, 0u);
  // Same kind within the period: held back, even with other numbers in it.
  EXPECT_FALSE(throttle.shouldReport("/a", "has no 'x' field", 101.0, suppressed));
  EXPECT_FALSE(throttle.shouldReport("/a", "has no 'x' field", 104.9, suppressed));
  // Another kind, or the same on another topic, is not hidden behind the first.
  EXPECT_TRUE(throttle.shouldReport("/a", "has no 'y' field", 101.0, suppressed));
  EXPECT_TRUE(throttle.shouldReport("/b", "has no 'x' field", 101.0, suppressed));
  // After the period: reported again, with the number held back meanwhile.
  EXPECT_TRUE(throttle.shouldReport("/a", "has no 'x' field", 105.0, suppressed));
  EXPECT_EQ(suppressed, 2u);
  EXPECT_FALSE(throttle.shouldReport("/a", "has no 'x' field", 106.0, suppressed));
}

TEST(ProblemThrottle, EverNewKindsCannotGrowItWithoutBound)
{
  ProblemThrottle throttle(5.0);
  std::size_t suppressed = 0;
  for (int k = 0; k < 10000; ++k)
    EXPECT_TRUE(throttle.shouldReport("/a", "kind " + std::string(1, static_cast<char>('a' + k % 26)) +
                                                std::string(static_cast<std::size_t>(k / 26), 'z'),
                                      1.0, suppressed));
}

}  // namespace
