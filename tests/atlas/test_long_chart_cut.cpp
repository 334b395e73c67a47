// Whether an atlas of long charts cut across their length is worth its added charts
// (atlas/long_chart_cut.h): hand-made figures against the stated trade, each relative increase
// of the chart count to be paid by at least kCoverageGainPerChartGain of it in coverage.
#include <gtest/gtest.h>

#include "atlas/long_chart_cut.h"

namespace harmonia {
namespace {

using detail::cut_worth_its_charts;

TEST(LongChartCut, ManyMoreChartsForALittleCoverageAreNotWorthIt) {
  // Three times the charts (+200 %) for +26 % coverage: under the +50 % they would have to buy.
  EXPECT_FALSE(cut_worth_its_charts(2, 0.43, 6, 0.54));
  // Half as many again for 1 % more.
  EXPECT_FALSE(cut_worth_its_charts(2, 0.541, 3, 0.547));
}

TEST(LongChartCut, ACutThatFillsTheAtlasIsWorthIt) {
  // A rod's strips that left most of the atlas empty: twice the charts, coverage doubled.
  EXPECT_TRUE(cut_worth_its_charts(10, 0.3, 20, 0.6));
  // A few charts more among hundreds, for a few percent of coverage.
  EXPECT_TRUE(cut_worth_its_charts(200, 0.60, 204, 0.62));
  // Just over the trade: +100 % charts for +27.5 % coverage.
  EXPECT_TRUE(cut_worth_its_charts(4, 0.4, 8, 0.51));
}

TEST(LongChartCut, NoGainInCoverageIsNeverWorthIt) {
  EXPECT_FALSE(cut_worth_its_charts(10, 0.5, 11, 0.5));
  EXPECT_FALSE(cut_worth_its_charts(10, 0.5, 12, 0.49));
  // An empty atlas before (nothing to compare with): any coverage gained is.
  EXPECT_TRUE(cut_worth_its_charts(0, 0.0, 2, 0.1));
}

}  // namespace
}  // namespace harmonia
