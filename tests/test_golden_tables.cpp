// Every shipped config by every method that applies, through the binary:
// the lobe table must equal the stored one byte for byte
// (tests/golden_cases.txt lists the cases, tests/data/golden/ holds the
// tables). A refactor must not change a number; a stored table changes only
// with a reason written in the commit that regenerates it:
//   grep -v '^#' tests/golden_cases.txt | while read stem method n extra; do
//     build/chatter lobes configs/$stem.toml --method $method --rpm-points $n
//       $extra --table tests/data/golden/$stem.$method.csv --quiet; done
// (one shell line).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.hpp"

namespace chatter::test {
namespace {

struct GoldenCase {
  std::string stem, method;
  std::vector<std::string> args;
};

std::vector<GoldenCase> read_cases() {
  std::ifstream in(std::string(CHATTER_SOURCE_DIR) + "/tests/golden_cases.txt");
  std::vector<GoldenCase> cases;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    GoldenCase c;
    std::string points, word;
    ss >> c.stem >> c.method >> points;
    c.args = {"lobes", std::string(CHATTER_SOURCE_DIR) + "/configs/" + c.stem + ".toml", "--method", c.method,
              "--rpm-points", points, "--quiet"};
    while (ss >> word) c.args.push_back(word);
    cases.push_back(c);
  }
  return cases;
}

class GoldenTables : public CliFixture {};

TEST_F(GoldenTables, EveryShippedConfigAndMethodByteIdentical) {
  const auto cases = read_cases();
  ASSERT_GE(cases.size(), 15u);
  for (const GoldenCase& c : cases) {
    SCOPED_TRACE(c.stem + " " + c.method);
    auto args = c.args;
    const fs::path table = path(c.stem + "." + c.method + ".csv");
    args.push_back("--table");
    args.push_back(table.string());
    const RunResult r = run(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string stored =
        slurp(fs::path(CHATTER_SOURCE_DIR) / "tests" / "data" / "golden" / (c.stem + "." + c.method + ".csv"));
    ASSERT_FALSE(stored.empty());
    EXPECT_EQ(slurp(table), stored);
  }
}

}  // namespace
}  // namespace chatter::test
