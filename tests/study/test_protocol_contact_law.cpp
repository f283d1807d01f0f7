// [clearance] contact_law / restitution of a study protocol: the default is the thesis's dashpot
// (and writes no new keys into the protocol's JSON, so older results stay byte-identical);
// "flores" is read with its restitution, `fit = ["restitution"]` is its dissipation parameter;
// an unknown law, an e outside [0.05, 1] and "restitution" with the dashpot fail naming the file,
// the line and the key.
#include <gtest/gtest.h>

#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/study/protocol.hpp"
#include "protocol_fixtures.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;

namespace {

const std::string kHead = std::string(clearshape::testing::kMiniProtocol) + "[clearance]\ninput = \"step\"\n";

std::string error_of(const std::string& clearance_lines) {
  return clearshape::testing::protocol_error_of(kHead + clearance_lines);
}

}  // namespace

TEST(ProtocolContactLaw, DefaultIsTheDashpotAndWritesNoKey) {
  const st::Protocol p = st::parse_protocol(kHead, "mini.toml");
  EXPECT_EQ(p.clearance.contact_law, "dashpot");
  const auto j = st::to_json(p);
  EXPECT_FALSE(j["clearance"].contains("contact_law"));
  EXPECT_FALSE(j["clearance"].contains("restitution"));
}

TEST(ProtocolContactLaw, FloresIsReadWithItsRestitution) {
  const st::Protocol p =
      st::parse_protocol(std::string(kHead) + "contact_law = \"flores\"\nrestitution = 0.7\nfit = [\"stiffness\", \"restitution\"]\n",
                         "mini.toml");
  EXPECT_EQ(p.clearance.contact_law, "flores");
  EXPECT_DOUBLE_EQ(p.clearance.restitution, 0.7);
  ASSERT_EQ(p.clearance.fit.size(), 2u);
  EXPECT_EQ(p.clearance.fit[1], "damping");  // the fit's dissipation slot: e with this law
  const auto j = st::to_json(p);
  EXPECT_EQ(j["clearance"]["contact_law"], "flores");
  EXPECT_DOUBLE_EQ(j["clearance"]["restitution"].get<double>(), 0.7);
}

TEST(ProtocolContactLaw, BadValuesNameFileLineAndKey) {
  const std::string e = error_of("contact_law = \"hertz\"\n");
  EXPECT_NE(e.find("mini.toml:12"), std::string::npos) << e;
  EXPECT_NE(e.find("clearance.contact_law"), std::string::npos) << e;
  EXPECT_NE(e.find("dashpot, flores"), std::string::npos) << e;
  const std::string e2 = error_of("contact_law = \"flores\"\nrestitution = 1.5\n");
  EXPECT_NE(e2.find("mini.toml:13"), std::string::npos) << e2;
  EXPECT_NE(e2.find("clearance.restitution"), std::string::npos) << e2;
  const std::string e3 = error_of("fit = [\"restitution\"]\n");  // the dashpot has no e
  EXPECT_NE(e3.find("clearance.fit"), std::string::npos) << e3;
  EXPECT_NE(e3.find("'restitution' cannot be fitted"), std::string::npos) << e3;
}
