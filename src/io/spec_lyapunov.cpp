// [measures] lyapunov = { vars = [...] }: the variables the tangent vector starts in.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/spec_reader.hpp"
#include "io/spec_suggestions.hpp"

namespace cs::spec {

void SpecReader::read_lyapunov(const toml::table& measures) {
  const toml::table* t = measure_settings(measures, "lyapunov", {"vars"});
  if (t == nullptr) return;
  // The tangent lives where the dynamics closes: (q, p), and z where z feeds back into them
  // (engine/measures/tangent_lyapunov.hpp). ln λ never does.
  Names usable;
  for (int k = 0; k < 2 * scene_->dof; ++k)
    usable.push_back(scene_->variables[static_cast<std::size_t>(k)].name);
  const Names default_vars = usable;
  if (scene_->z_feeds_back) usable.push_back("z");
  const toml::node* vars = t->get("vars");
  if (vars == nullptr) {
    spec_.measures.lyapunov = LyapunovMeasure{default_vars};
    return;
  }
  const char* key = "measures.lyapunov.vars";
  const toml::array& list = array(*vars, key);
  if (list.empty())
    fail_value(*vars, key,
               fmt::format("at least one of {} (or lyapunov = false)", fmt::join(usable, ", ")));
  Names chosen;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string item = fmt::format("{}[{}]", key, i);
    const std::string var = string(*list.get(i), item);
    if (!contains(usable, var)) {
      const std::string why =
          var == "z" ? "; z does not feed back into this K's dynamics, so the tangent leaves it out"
          : var == "lambda" ? "; lambda never feeds back into the dynamics"
                            : did_you_mean(var, usable, "");
      fail_value(*list.get(i), item,
                 fmt::format("a variable the tangent vector can start in: {}{}",
                             fmt::join(usable, ", "), why));
    }
    if (contains(chosen, var)) fail_value(*list.get(i), item, "each variable once");
    chosen.push_back(var);
  }
  spec_.measures.lyapunov = LyapunovMeasure{chosen};
}

}  // namespace cs::spec
