// Cluster::agree (render/cluster.cpp), the rule that makes every MPI rank fail alike: with a
// stand-in for rank 0 of two ranks (its collective calls answered as rank 1 would answer),
// rank 1's failure reaches rank 0 with rank 1's code and message; rank 0's own failure wins
// over a higher rank's; with no failure nothing is thrown. Alone, agree rethrows as is.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "render/cluster.h"
#include "util/error.h"

namespace clpt::cluster_test {
namespace {

// Rank 0 of two; rank 1 failed with `code` (or not, code < 0) and `message`.
class TwoRanks : public Cluster {
 public:
  TwoRanks(double code, std::string message) : code_(code), message_(std::move(message)) {}
  int rank() const override { return 0; }
  int size() const override { return 2; }
  std::vector<double> all_gather(const std::vector<double>& mine) const override {
    std::vector<double> all = mine;
    all.push_back(code_);
    return all;
  }
  void broadcast(std::string& text, int root) const override {
    if (root == 1) text = message_;
  }

 private:
  double code_;
  std::string message_;
};

std::exception_ptr usage_error(const std::string& what) {
  return capture([&] { throw Error(ExitCode::Usage, what); });
}

TEST(ClusterAgree, AnotherRanksFailureFailsThisRankWithItsCodeAndMessage) {
  const TwoRanks cluster(2.0, "/x/scene.gltf: file not found");
  try {
    cluster.agree(nullptr);
    FAIL() << "rank 1 failed, so rank 0 must throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::BadInput);
    EXPECT_EQ(std::string(e.what()), "rank 1: /x/scene.gltf: file not found");
  }
}

TEST(ClusterAgree, TheLowestFailingRankSpeaks) {
  const TwoRanks cluster(3.0, "device lost");
  try {
    cluster.agree(usage_error("--spp must be positive"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Usage);
    EXPECT_EQ(std::string(e.what()), "--spp must be positive");
  }
  // Exceptions other than clpt's keep their exit codes: out of memory is a device problem
  // (3), anything else an internal error (70).
  try {
    cluster.agree(capture([] { throw std::bad_alloc(); }));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(static_cast<int>(e.code()), 3);
  }
  try {
    cluster.agree(capture([] { throw std::logic_error("oops"); }));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(static_cast<int>(e.code()), 70);
    EXPECT_NE(std::string(e.what()).find("oops"), std::string::npos);
  }
}

TEST(ClusterAgree, NoFailureThrowsNothingAndAloneRethrowsAsIs) {
  EXPECT_NO_THROW(TwoRanks(-1.0, "").agree(nullptr));
  const Cluster alone;
  EXPECT_NO_THROW(alone.agree(nullptr));
  EXPECT_THROW(alone.agree(capture([] { throw std::logic_error("as is"); })), std::logic_error);
}

}  // namespace
}  // namespace clpt::cluster_test
