// The integrator table (host/integrators/integrator.cpp) against what the command line does
// with each row: the checks read the table, so a row that claims a film kind or an option
// group the checks do not honour fails here.
//   IntegratorTable.NamesAreUniqueAndHelpListsThem   every row once, all in --help's list
//   IntegratorTable.VarianceAndCheckpointsFollowTheFilm  --variance and --checkpoint are
//       accepted exactly for rows whose film holds sample sums
//   IntegratorTable.OptionGroupsBelongToTheirRows    an option of a group parses exactly
//       with the rows that read that group
//   IntegratorTable.UnimplementedRowsHaveNoFactory   implemented exactly when there is a factory
//   IntegratorTable.RowsSayWhatTheReadmeSays         each implemented row against the README
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "options.h"
#include "util/error.h"

namespace integrator_table_test {
namespace {

using clpt::FilmKind;
using clpt::IntegratorInfo;

// Whether `clpt scene.gltf ARGS...` is a valid command line (parsing only: no file is read).
bool parses(const std::vector<std::string>& args) {
  std::vector<const char*> argv{"clpt", "scene.gltf"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    return clpt::parse_options(static_cast<int>(argv.size()), argv.data()).has_value();
  } catch (const clpt::Error& e) {
    EXPECT_EQ(e.code(), clpt::ExitCode::Usage) << e.what();
    return false;
  }
}

TEST(IntegratorTable, NamesAreUniqueAndHelpListsThem) {
  std::set<std::string> names;
  const std::string help = clpt::usage_text();
  for (const IntegratorInfo& row : clpt::integrator_table()) {
    EXPECT_TRUE(names.insert(row.name).second) << row.name << " twice";
    EXPECT_NE(help.find(row.name), std::string::npos) << row.name;
    EXPECT_EQ(clpt::find_integrator(row.name), &row);
  }
  EXPECT_EQ(clpt::find_integrator("nope"), nullptr);
  EXPECT_FALSE(parses({"--integrator", "nope"}));
}

TEST(IntegratorTable, VarianceAndCheckpointsFollowTheFilm) {
  for (const IntegratorInfo& row : clpt::integrator_table()) {
    const bool sums = row.film == FilmKind::SampleSums;
    EXPECT_TRUE(parses({"--integrator", row.name})) << row.name;
    EXPECT_EQ(parses({"--integrator", row.name, "--variance"}), sums) << row.name;
    EXPECT_EQ(parses({"--integrator", row.name, "--checkpoint", "x.ckpt"}), sums) << row.name;
  }
}

TEST(IntegratorTable, OptionGroupsBelongToTheirRows) {
  struct Group {
    unsigned bit;
    std::vector<std::string> option;
  };
  const std::vector<Group> groups = {
      {clpt::OPTIONS_PHOTONS, {"--photons", "1000"}},
      {clpt::OPTIONS_PM, {"--knn", "10"}},
      {clpt::OPTIONS_PM, {"--final-gather", "2"}},
      {clpt::OPTIONS_SPPM, {"--sppm-alpha", "0.5"}},
      {clpt::OPTIONS_LVC, {"--bdpt-lvc", "2"}},
      {clpt::OPTIONS_VCM, {"--vcm-mode", "bpt"}},
      {clpt::OPTIONS_VCM, {"--vcm-merged"}},
      {clpt::OPTIONS_BDPT, {"--bdpt-strategy", "2,2"}},
      {clpt::OPTIONS_AO, {"--ao-radius", "0.5"}},
  };
  for (const IntegratorInfo& row : clpt::integrator_table())
    for (const Group& g : groups) {
      std::vector<std::string> args = {"--integrator", row.name};
      args.insert(args.end(), g.option.begin(), g.option.end());
      EXPECT_EQ(parses(args), (row.options & g.bit) != 0u) << row.name << " " << g.option[0];
    }
}

TEST(IntegratorTable, UnimplementedRowsHaveNoFactory) {
  const std::string text = clpt::integrator_names_text(",", true) + ",";
  std::set<std::string> implemented;
  for (size_t a = 0, b; (b = text.find(',', a)) != std::string::npos; a = b + 1)
    implemented.insert(text.substr(a, b - a));
  for (const IntegratorInfo& row : clpt::integrator_table()) {
    EXPECT_EQ(row.implemented, row.make != nullptr) << row.name;
    EXPECT_EQ(implemented.count(row.name) == 1u, row.implemented) << row.name;
  }
}

}  // namespace

// The other checks compare the command line with the table, which it reads; this one holds
// the table to the README's promises for each implemented integrator, written out again here
// on purpose so that a wrong row fails.
TEST(IntegratorTable, RowsSayWhatTheReadmeSays) {
  struct Promise {
    const char* name;
    FilmKind film;
    unsigned options;
    bool needs_lights, needs_perspective;
  };
  const std::vector<Promise> promises = {
      {"pt", FilmKind::SampleSums, clpt::OPTIONS_NONE, true, false},
      {"lt", FilmKind::Splats, clpt::OPTIONS_NONE, true, true},
      {"bdpt", FilmKind::Splats, clpt::OPTIONS_BDPT | clpt::OPTIONS_LVC, true, true},
      {"pm", FilmKind::SampleSums, clpt::OPTIONS_PHOTONS | clpt::OPTIONS_PM, true, false},
      {"sppm", FilmKind::Progressive, clpt::OPTIONS_PHOTONS | clpt::OPTIONS_SPPM, true, false},
      {"vcm", FilmKind::Splats, clpt::OPTIONS_VCM | clpt::OPTIONS_LVC, true, true},
      {"mlt", FilmKind::Splats, clpt::OPTIONS_MLT, true, false},
      {"ic", FilmKind::SampleSums, clpt::OPTIONS_IC, true, false},
      {"ao", FilmKind::SampleSums, clpt::OPTIONS_AO, false, false},
      {"direct", FilmKind::SampleSums, clpt::OPTIONS_NONE, true, false},
  };
  for (const Promise& p : promises) {
    const IntegratorInfo* row = clpt::find_integrator(p.name);
    ASSERT_NE(row, nullptr) << p.name;
    EXPECT_TRUE(row->implemented) << p.name;
    EXPECT_EQ(row->film, p.film) << p.name;
    EXPECT_EQ(row->options, p.options) << p.name;
    EXPECT_EQ(row->needs_lights, p.needs_lights) << p.name;
    EXPECT_EQ(row->needs_perspective_camera, p.needs_perspective) << p.name;
  }
  EXPECT_EQ(clpt::find_integrator("direct")->max_depth_cap, 1u);
  EXPECT_TRUE(clpt::find_integrator("lt")->traces_light_paths);
}

}  // namespace integrator_table_test
