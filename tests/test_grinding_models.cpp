// The grinding engineer's models beyond one prediction (docs/grinding.md):
// beta of the power partition by power and feed (seed 001 table 2.2), ...
// Each number against the seed's table or a hand computation.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/grinding.hpp"
#include "grinding_cases.hpp"

namespace chatter::grinding {
namespace {

constexpr double kIdentityRel = 1e-12;

// Seed 001 table 2.2: beta by feed (mm/s) and power (W), alpha = 0.76.
BetaTable seed001_table_2_2() {
  return BetaTable({{0.040, {1000, 1250, 1500}, {0.49, 0.33, 0.20}},
                    {0.060, {1000, 1250, 1500, 1750}, {0.36, 0.21, 0.13, 0.08}},
                    {0.080, {1000, 1250, 1500, 1750, 2000}, {0.27, 0.17, 0.09, 0.05, 0.03}}});
}

TEST(GrindingBetaTable, NodesAreTheSeedsTable) {
  const BetaTable t = seed001_table_2_2();
  std::vector<std::string> notes;
  EXPECT_EQ(t.at(1000, 0.040, &notes), 0.49);
  EXPECT_EQ(t.at(1750, 0.060, &notes), 0.08);
  EXPECT_EQ(t.at(2000, 0.080, &notes), 0.03);
  EXPECT_EQ(t.at(1250, 0.080, &notes), 0.17);
  EXPECT_TRUE(notes.empty());
}

TEST(GrindingBetaTable, InterpolatedInPowerThenFeedAndHeldWithANote) {
  const BetaTable t = seed001_table_2_2();
  std::vector<std::string> notes;
  // 70 mm/s, 1125 W: rows 60 and 80 at 1125 W are 0.285 and 0.22, halfway 0.2525.
  EXPECT_NEAR(t.at(1125, 0.070, &notes), 0.5 * (0.5 * (0.36 + 0.21) + 0.5 * (0.27 + 0.17)), kIdentityRel);
  EXPECT_TRUE(notes.empty());
  // 70 mm/s, 1900 W: the 60 mm/s row ends at 1750 W (held at 0.08); the
  // 80 mm/s row gives 0.05 + 0.6 (0.03 - 0.05) = 0.038; halfway 0.059.
  EXPECT_NEAR(t.at(1900, 0.070, &notes), 0.5 * (0.08 + 0.038), kIdentityRel);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("60 mm/s"), std::string::npos) << notes[0];
  // Beyond the feeds: the nearest row, said.
  notes.clear();
  EXPECT_EQ(t.at(1500, 0.100, &notes), 0.09);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("100 mm/s"), std::string::npos) << notes[0];
}

TEST(GrindingBetaTable, RefusesWhatIsNotATable) {
  EXPECT_THROW(BetaTable(std::vector<BetaTable::Row>{}), InputError);
  EXPECT_THROW(BetaTable({{0.08, {1000, 900}, {0.2, 0.1}}}), InputError);             // powers not increasing
  EXPECT_THROW(BetaTable({{0.08, {1000}, {1.2}}}), InputError);                       // beta > 1
  EXPECT_THROW(BetaTable({{0.08, {1000}, {0.2}}, {0.06, {1000}, {0.3}}}), InputError);  // feeds not increasing
  EXPECT_THROW(BetaTable({{0.08, {1000, 1500}, {0.2}}}), InputError);                 // one beta per power
}

// The power partition (seed 001 eq. 2.18) at each power of table 4.1 with
// the 80 mm/s row: eps = (0.76 P_friction + beta P_chip) / P from the
// prediction's own split, and the record carries the beta used.
TEST(GrindingBetaTable, PowerPartitionReadsBetaAtItsPowerAndFeed) {
  Process p = cases::seed001_ch4();
  p.partition->model = PartitionModel::kPower;
  p.partition->alpha = 0.76;
  p.partition->beta_table = seed001_table_2_2();
  const double beta[] = {0.27, 0.17, 0.09, 0.05, 0.03};
  for (int i = 0; i < 5; ++i) {
    const double P = 1000.0 + 250.0 * i;
    const Prediction r = predict_at_power(p, P);
    ASSERT_TRUE(r.energy_partition && r.energy_partition->beta);
    EXPECT_EQ(*r.energy_partition->beta, beta[i]);
    EXPECT_NEAR(r.energy_partition->fraction, (0.76 * *r.friction_power_w + beta[i] * *r.chip_power_w) / P,
                kIdentityRel);
  }
  // At 60 mm/s the 60 mm/s row: 1250 W -> 0.21.
  p.feed_m_per_s = 0.060;
  EXPECT_EQ(*predict_at_power(p, 1250).energy_partition->beta, 0.21);
  // Past 1750 W at 60 mm/s: held, and a warning says so.
  const Prediction h = predict_at_power(p, 2000);
  EXPECT_EQ(*h.energy_partition->beta, 0.08);
  bool said = false;
  for (const auto& w : h.warnings) said = said || w.find("beta table") != std::string::npos;
  EXPECT_TRUE(said);
}

}  // namespace
}  // namespace chatter::grinding
