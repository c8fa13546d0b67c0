// Writes the scene headers of the K-defined benchmark cases, as `contactsweep run` generates
// them for a spec's scene.K (formula/scene_codegen.cpp): the benchmark then times the kernel a
// user's K gets.   k_scenes_gen OUTPUT_DIR
#include <fstream>
#include <iostream>

#include "formula/k_formula.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: k_scenes_gen OUTPUT_DIR\n";
    return 2;
  }
  struct Written {
    const char* file;
    const char* name;
    const char* k;
  };
  // The spellings of sweeps/basins_double_well_k.toml, basins_forced_duffing.toml and
  // basins_magnetic_pendulum.toml.
  const Written scenes[] = {
      {"k_double_well.hpp", "KDoubleWell", "p^2/2 + (q^2 - a^2)^2/2 - gamma*z"},
      {"k_forced_duffing.hpp", "KForcedDuffing",
       "p^2/2 - q^2/2 + q^4/4 - F*q*cos(Omega*t) - delta*z"},
      {"k_magnetic_pendulum.hpp", "KMagneticPendulum",
       "(p1^2 + p2^2)/2 + w^2*(q1^2 + q2^2)/2 - 1/sqrt((q1 - 1)^2 + q2^2 + d^2)"
       " - 1/sqrt((q1 + 0.5)^2 + (q2 - 0.8660254037844386)^2 + d^2)"
       " - 1/sqrt((q1 + 0.5)^2 + (q2 + 0.8660254037844386)^2 + d^2) - gamma*z"},
  };
  for (const auto& s : scenes) {
    const std::string path = std::string(argv[1]) + "/" + s.file;
    std::ofstream out(path);
    out << cs::scene_header(cs::parse_k(s.k), s.name);
    if (!out.flush()) {
      std::cerr << "k_scenes_gen: cannot write " << path << "\n";
      return 1;
    }
  }
  return 0;
}
