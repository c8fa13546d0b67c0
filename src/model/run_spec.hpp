// A validated run: what a spec file (after --set overrides) asks for, with every default filled in
// from the scene catalog. Everything downstream (engine, HDF5 writer) trusts it; all checking of
// user input happens while building it (io/spec_parser.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cs {

// Bad user input (spec, command line): the program exits with status 2 and prints what().
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One grid axis: a scene parameter ("gamma") or an initial value ("q_0").
struct GridAxis {
  std::string name;            // as in the spec and as the HDF5 coordinate: "q_0", "gamma"
  std::string target;          // parameter or variable it sets: "q", "gamma"
  bool is_parameter = false;   // true: scene parameter; false: initial value of a variable
  bool is_step_size = false;   // the axis "h": the integrator's step (first axis only; each
                               // value is integrated as its own slice of the grid)
  std::vector<double> values;  // numpy.linspace(from, to, n) bit for bit, or explicit values
};

struct FinalStateMeasure {
  std::vector<std::string> vars;  // state variable names to store ("q", "p", "z", "lambda")
};

struct TrajectoryMeasure {
  std::int64_t every = 1;         // sample every this many steps (t = 0 included)
};

// Basins (INTERFACE.md, "Basins of any system"). A lane settles when its (q, p) stays within
// `tolerance` (max norm) of a fixed point, or of a period-m cycle of the stroboscopic map at
// t_start + k·period, for `dwell` time units; its attractor then joins the run's table.
// The recurrence mapper (engine/recurrence/, Attractors.jl's AttractorsViaRecurrences): a grid
// of cells over phase space, in which a lane settles when it keeps revisiting a bounded set.
struct RecurrenceSettings {
  std::optional<bool> enabled;      // none: on unless K proves every attractor a fixed point
  std::optional<double> cell_size;  // none: the box's widest side / kDefaultCellsAcross
  std::int64_t recurrences = 100;   // revisits in a row that find an attractor
  std::int64_t locate = 1000;       // samples after them whose cells are the attractor's
  std::int64_t max_cells = 16384;   // cells a lane may visit before it gives up
  std::map<std::string, std::array<double, 2>> box;  // variable → [lo, hi]; else from the grid
  static constexpr double kDefaultCellsAcross = 100.0;
};

struct BasinMeasure {
  bool early_stop = true;
  std::optional<double> period;          // the forcing period (stroboscopic map); none: looks
  double tolerance = 1e-3;
  double dwell = 0.0;                    // time units; filled in from the defaults below
  int max_period = 1;                    // longest cycle of the stroboscopic map looked for
  bool exact_trap = true;                // use the scene's exact energy trap where it has one
  std::map<std::string, double> angles;  // variable → its period (compared modulo it)
  // How far an attractor may move between neighbouring values of a continuation axis and keep
  // its label; none: a tenth of the map's box (engine/attractor_continuation.hpp).
  std::optional<double> continuation_threshold;
  RecurrenceSettings recurrence;
  static constexpr double kDefaultDwell = 20.0;          // time units, autonomous
  static constexpr double kDefaultDwellPeriods = 16.0;   // periods, stroboscopic
  static constexpr int kDefaultMaxPeriod = 8;            // with a period
  static constexpr int kMaxPeriodLimit = 8;  // CycleTracker::kMaxPeriod
};

// Synchronization of two degrees of freedom i, j of any scene (dof ≥ 2): phases
// θ_k = atan2(−p_k/ω_k, q_k), their mean frequencies measured over the window. ω_k only scales
// p_k so that a harmonic oscillation turns the phase uniformly; it defaults to 1, and to the
// scene's own frequencies for coupled_oscillators.
struct SyncMeasure {
  double window_from = 0.0;
  double window_to = 0.0;
  int dof[2] = {0, 1};                    // 0-based here; 1-based in the spec (`dof = [1, 2]`)
  std::optional<std::array<double, 2>> omega;
};

// The finite-time largest Lyapunov exponent (engine/measures/tangent_lyapunov.hpp): the
// tangent vector starts with equal components in `vars` (q.., p.., and z where z feeds back).
struct LyapunovMeasure {
  std::vector<std::string> vars;
};

// Observables and events as formulas (docs/observables.md; formula/measure_formulas.hpp).
struct ObserveMeasure {
  std::vector<std::pair<std::string, std::string>> formulas;  // name → formula, in spec order
  std::optional<std::array<double, 2>> window;                // observe_window {from, to}
};

struct StopMeasure {
  std::string when;                // the condition
  std::string label;               // exit channel as a formula ("" if none)
  std::vector<std::string> exits;  // or as conditions, the first that holds (1-based)
};

struct Measures {
  std::optional<FinalStateMeasure> final_state;
  std::optional<TrajectoryMeasure> trajectory;
  std::optional<BasinMeasure> basin;
  std::optional<SyncMeasure> sync;
  std::optional<LyapunovMeasure> lyapunov;
  std::optional<ObserveMeasure> observe;
  std::optional<StopMeasure> stop;
};

struct CustomScene;  // formula/custom_scene.hpp

struct RunSpec {
  std::string title;
  std::string scene;                         // a name from scene_catalog(), or a custom label
  std::shared_ptr<const CustomScene> custom; // set when the spec writes K itself
  std::map<std::string, double> parameters;  // every scene parameter (defaults filled in)
  std::map<std::string, double> initial;     // every state variable (defaults filled in)
  std::string method;                        // a name from method_catalog()
  double h = 0.0;
  double t_start = 0.0;                      // the time of the initial state
  double t_end = 0.0;
  std::int64_t steps = 0;                    // (t_end − t_start) / h, a whole number (checked);
                                             // for an adaptive method the nearest whole number
                                             // (block sizes, progress), its lanes step to t_end
  // An adaptive method's tolerances (integrator.rtol, atol; required by it, refused by the
  // others): each lane's local error estimate is kept below atol + rtol·|y| (h: its first step).
  double rtol = 0.0, atol = 0.0;
  std::vector<GridAxis> axes;                // first varies slowest; empty: one trajectory
  Measures measures;
  std::string spec_text;                     // the TOML after --set, as stored in the output

  // The product of the axis lengths (1 without axes).
  std::int64_t grid_points() const {
    std::int64_t points = 1;
    for (const GridAxis& axis : axes) points *= std::ssize(axis.values);
    return points;
  }
};

}  // namespace cs
