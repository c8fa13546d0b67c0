// The built-in scenes come from one source, src/physics/scenes.toml: the headers the kernel is
// compiled for and the run-time catalog must describe the same scenes, and the generated K must
// be the paper's K (checked against GiNaC's exact value of the catalog's formula).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "formula/k_formula.hpp"
#include "physics/builtin_scenes.hpp"
#include "physics/partials.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {
namespace {

template <class S>
void expect_header_matches_catalog() {
  SCOPED_TRACE(S::name);
  const SceneInfo* info = find_scene(S::name);
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(info->dof, S::dof);
  EXPECT_EQ(info->z_feeds_back, S::z_feeds_back);
  EXPECT_EQ(info->variables.size(), static_cast<std::size_t>(2 * S::dof + 2));
  ASSERT_EQ(info->parameters.size() * sizeof(double), sizeof(ParamsOf<S, double>));

  // K of the compiled header at a state and the catalog's parameter values against the exact
  // value of the catalog's formula: the same K, to the last bit where GiNaC rounds once and the
  // header rounds at every operation (a few ulps).
  const KFormula f = parse_k(info->hamiltonian.substr(4));  // "K = ..."
  std::map<std::string, double> values;
  std::vector<double> params;
  for (const auto& p : info->parameters) values[p.name] = p.paper_value, params.push_back(p.paper_value);
  double q[S::dof], p[S::dof];
  for (int d = 0; d < S::dof; ++d) {
    q[d] = 0.3 + 0.7 * d, p[d] = -0.4 + 0.25 * d;
    values[f.positions[d]] = q[d], values[f.momenta[d]] = p[d];
  }
  values["z"] = 0.6;
  const auto c = S::params_from(params.data());
  const double compiled = K<S>(q, p, 0.6, c, 0.0);
  EXPECT_NEAR(compiled, evaluate_k(f, values), 4e-16 * std::fabs(compiled));
  const double compiled_kz = K_z<S>(q, p, 0.6, c, 0.0);
  EXPECT_NEAR(compiled_kz, evaluate_k(f, values, "z"), 4e-16 * std::fabs(compiled_kz));
}

template <class... Scenes>
void expect_all(SceneList<Scenes...>) {
  (expect_header_matches_catalog<Scenes>(), ...);
}

TEST(SceneCatalog, EveryGeneratedHeaderMatchesItsCatalogEntry) {
  expect_all(BuiltinScenes{});
  EXPECT_EQ(scene_catalog().size(), 4u);
}

TEST(SceneCatalog, PaperScenesInThePapersOrderWithThePapersValues) {
  const auto& all = scene_catalog();
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[0].name, "damped_oscillator");
  EXPECT_EQ(all[3].name, "coupled_oscillators");
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i].paper_label, std::string(1, char('A' + i)));
  // Scene D: the paper's omega1^2 = 1.2, omega2^2 = 0.8, g = 0.8, gamma = 0.01, from (1, -1).
  EXPECT_EQ(all[3].parameters[0].name, "omega1_sq");
  EXPECT_EQ(all[3].parameters[0].paper_value, 1.2);
  EXPECT_EQ(all[3].variables[1].name, "q2");
  EXPECT_EQ(all[3].variables[1].paper_value, -1.0);
  EXPECT_EQ(all[1].split_parts, (std::vector<std::string>{"kinetic", "potential", "z_quadratic"}));
  EXPECT_TRUE(all[1].z_feeds_back);
}

TEST(SceneCatalog, TraitsAreDerivedFromK) {
  // Scene B's K_z = -2 gamma z reads z: it feeds back and is not constant; the others' is -gamma.
  EXPECT_TRUE(Z2Damping::z_feeds_back);
  EXPECT_FALSE(Z2Damping::kz_constant);
  EXPECT_TRUE(DoubleWell::kz_constant);
  EXPECT_FALSE(DoubleWell::time_dependent);
  EXPECT_EQ(DoubleWell::z_part, ZPart::linear);
  EXPECT_EQ(Z2Damping::z_part, ZPart::quadratic);
}

TEST(SceneCatalog, NaturalFrequenciesAreTheSquareRootsOfTheSquaredOnes) {
  const double v[] = {1.2, 0.8, 0.8, 0.01};
  double omega[2];
  CoupledOscillators::natural_frequencies(CoupledOscillators::params_from(v), omega);
  EXPECT_EQ(omega[0], std::sqrt(1.2));
  EXPECT_EQ(omega[1], std::sqrt(0.8));
}

TEST(SceneCatalog, TheDoubleWellsLabelsFollowTheSignOfQ) {
  const SceneInfo* well = find_scene("double_well");
  ASSERT_NE(well, nullptr);
  EXPECT_EQ(well->label_rule.kind, LabelRule::Kind::sign_of_q1);
  EXPECT_EQ(well->label_rule.negative, "left_well");
  EXPECT_EQ(well->label_rule.positive, "right_well");
  EXPECT_EQ(find_scene("damped_oscillator")->label_rule.kind, LabelRule::Kind::numbered);
}

}  // namespace
}  // namespace cs
