// Reading the parsed spec (after --set) into a RunSpec: one reader, its sections in files of
// their own (spec_scene.cpp, spec_integrator.cpp, spec_grid.cpp, spec_measures.cpp), the
// messages and typed access they share in spec_reader.cpp. Decisions: spec_parser.hpp.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/spec_names.hpp"
#include "model/run_spec.hpp"
#include "physics/scene_catalog.hpp"

namespace cs::spec {

// The engine flattens the grid into one int64 index and the output holds every point; 2^40 is
// far beyond any run that could finish, and checking it keeps the size product from overflowing.
inline constexpr std::int64_t kMaxGridPoints = std::int64_t{1} << 40;
// Every rank holds every coordinate vector: 2^32 doubles are already 32 GiB.
inline constexpr std::int64_t kMaxAxisPoints = std::int64_t{1} << 32;
// Beyond 2^53 steps a double can no longer count them (t = k h loses k).
inline constexpr double kMaxSteps = 9007199254740992.0;
// t_end is a whole number of steps when steps * h is within this of t_end, relative to t_end.
inline constexpr double kStepTolerance = 1e-9;

inline constexpr std::string_view kMeasureNames[] = {"final_state", "trajectory", "basin", "sync",
                                                     "lyapunov", "observe", "observe_window",
                                                     "stop"};

template <class Info>
Names names_of(const std::vector<Info>& infos) {
  Names names;
  for (const Info& info : infos) names.push_back(info.name);
  return names;
}

inline Names variable_names(const SceneInfo& scene) { return names_of(scene.variables); }
inline Names parameter_names(const SceneInfo& scene) { return names_of(scene.parameters); }

// lambda is an integrating factor and the kernel carries ln(lambda).
inline bool must_be_positive(std::string_view variable) { return variable == "lambda"; }

class SpecReader {
 public:
  SpecReader(const toml::table& doc, std::string_view source_name, Names grid_order)
      : doc_(doc), source_name_(source_name), grid_order_(std::move(grid_order)) {}

  RunSpec read();

 private:
  struct AxisDraft {
    GridAxis axis;  // values already set for { values = [...] }
    const toml::node* node;
    double from = 0.0, to = 0.0;
    std::int64_t n = 0;  // > 0: values still to come from linspace(from, to, n)
    std::int64_t size() const { return n > 0 ? n : std::ssize(axis.values); }
  };

  // --- messages ------------------------------------------------------------------------------
  // "file:line:column", or the --set argument a node came from, or the file alone.
  std::string where(const toml::node* at) const;
  [[noreturn]] void fail(const toml::node* at, std::string_view message) const;
  [[noreturn]] void fail_type(const toml::node& node, std::string_view key,
                              std::string_view expected) const;
  [[noreturn]] void fail_value(const toml::node& node, std::string_view key,
                               std::string_view expected) const;
  // Every key of `table` must be in `allowed`; otherwise name it and suggest the likely one.
  void check_keys(const toml::table& table, std::string_view prefix, const Names& allowed) const;
  // A key that belongs to another section ("gamma" under [integrator]) points there.
  std::string elsewhere_hint(std::string_view key, std::string_view prefix) const;
  Names known_paths() const;
  static Names top_level_keys();

  // --- typed access --------------------------------------------------------------------------
  double number(const toml::node& node, std::string_view key) const;
  std::int64_t integer(const toml::node& node, std::string_view key) const;
  bool boolean(const toml::node& node, std::string_view key) const;
  std::string string(const toml::node& node, std::string_view key) const;
  const toml::table& table(const toml::node& node, std::string_view key) const;
  const toml::array& array(const toml::node& node, std::string_view key) const;
  std::vector<double> numbers(const toml::node& node, std::string_view key) const;
  // A top-level section; an absent one reads as empty so that every default applies.
  const toml::table& section(std::string_view name) const;
  double number_or(const toml::table& t, std::string_view prefix, std::string_view key,
                   double fallback) const;

  // --- [scene], [initial], title ------------------------------------------------------------
  void read_scene();
  // [scene] K = "...": every symbol of K that is not a variable is a parameter valued here, and
  // every other key must be a parameter of K (or label).
  void read_custom_scene(const toml::table& t, const toml::node& k);
  void read_initial();
  void read_title();

  // --- [integrator] --------------------------------------------------------------------------
  void read_integrator();
  void read_method(const toml::table& t);
  Names usable_methods() const;
  void read_tolerances(const toml::table& t);
  // Measures an adaptive method does not support yet: an InputError naming them.
  void check_adaptive_measures() const;
  // How messages name the run's duration: plain t_end for the common start at 0.
  std::string duration_name() const;
  // (t_end − t_start) / h as a whole number of steps; `at` is the node to blame (t_end, else h,
  // else none).
  std::int64_t whole_steps(const toml::node* at) const;

  // --- [grid] --------------------------------------------------------------------------------
  void read_grid();
  // Scene parameters by name, initial values as <variable>_0.
  Names axis_names() const;
  AxisDraft read_axis(const std::string& name, const toml::node& node) const;
  void check_grid_size(const std::vector<AxisDraft>& drafts) const;
  void check_axis_values(const AxisDraft& draft) const;
  // A grid over h integrates each h as its own slice: it must be the first axis (slices are
  // then contiguous), and every h must divide t_end into whole steps.
  void check_step_size(const AxisDraft& draft, double h) const;

  // --- [measures] ----------------------------------------------------------------------------
  void read_measures();
  // The settings of one measure: nullptr when absent or false; `true` reads as empty settings.
  const toml::table* measure_settings(const toml::table& measures, std::string_view name,
                                      const Names& keys) const;
  void read_final_state(const toml::table& measures);
  void read_trajectory(const toml::table& measures);
  void read_basin(const toml::table& measures);
  // The stroboscopic map samples every period/h steps: a whole number for every step size.
  void read_basin_period(const toml::node& node, BasinMeasure& basin);
  double read_continuation_threshold(const toml::node& node);
  // The recurrence mapper's keys: recurrence, cell_size, recurrences, locate, max_cells, box.
  void read_basin_recurrence(const toml::table& t, RecurrenceSettings& r);
  void read_sync(const toml::table& measures);
  // Which two degrees of freedom, and the frequencies that scale their momenta.
  void read_sync_pair(const toml::table& t, SyncMeasure& sync);
  void read_lyapunov(const toml::table& measures);  // spec_lyapunov.cpp
  // observe, observe_window and stop: measures as formulas (spec_observe.cpp).
  void read_observe(const toml::table& measures);
  void read_stop(const toml::table& measures);

  const toml::table& doc_;
  std::string source_name_;
  Names grid_order_;
  const SceneInfo* scene_ = nullptr;
  RunSpec spec_;
};

}  // namespace cs::spec
