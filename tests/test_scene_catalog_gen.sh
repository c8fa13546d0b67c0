#!/usr/bin/env bash
# The generator of the built-in scenes (src/formula/scene_catalog_gen.cpp) on a data file: a
# good entry gives a header that compiles and a catalog; a bad one exits 1, names the scene and
# what is wrong, and writes nothing.
#   test_scene_catalog_gen.sh SCENE_CATALOG_GEN SOURCE_DIR CXX
# Last line: "N passed, M failed". Exit status 1 if any failed.
set -uo pipefail
gen=$1 src=$2 cxx=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0 failed=0

entry() {  # entry NAME K PARAMETERS VARIABLES [EXTRA...]
  printf '[[scene]]\nname = "%s"\npaper_label = "X"\nK = "%s"\nparameters = [%s]\nvariables = [%s]\ndefault_h = 0.01\ndefault_t_end = 10.0\n' "$1" "$2" "$3" "$4"
  shift 4
  for line in "$@"; do printf '%s\n' "$line"; done
}
one_dof_vars='{ name = "q", value = 1.0, description = "x" }, { name = "p", value = 0.0, description = "x" }, { name = "z", value = 0.0, description = "x" }, { name = "lambda", value = 1.0, description = "x" }'
k_params='{ name = "k", value = 2.0, description = "stiffness" }, { name = "gamma", value = 0.1, description = "damping" }'

check() {  # check NAME STATUS FRAGMENT FILE
  local name=$1 status=$2 fragment=$3 file=$4 rc=0 why=()
  rm -rf "$work/out"
  "$gen" "$file" "$work/out" >"$work/stdout" 2>"$work/stderr" || rc=$?
  [[ $rc == "$status" ]] || why+=("exit $rc, expected $status")
  [[ -z $fragment ]] || grep -qF -- "$fragment" "$work/stderr" || why+=("stderr lacks '$fragment'")
  if [[ $status != 0 && -e $work/out ]]; then why+=("wrote $(find "$work/out" -type f | head -1)"); fi
  if ((${#why[@]})); then
    echo "FAIL $name: ${why[*]}"; sed 's/^/    /' "$work/stderr"; failed=$((failed + 1))
  else
    echo "ok   $name"; passed=$((passed + 1))
  fi
}

# A good scene: the header compiles, K is written in the declared parameter order, and the
# natural frequency is the formula given.
entry spring_well "p^2/2 + k*(q^2/2) - gamma*z" "$k_params" "$one_dof_vars" \
  'natural_frequencies = ["sqrt(k)"]' >"$work/good.toml"
check good 0 "" "$work/good.toml"
if [[ -f $work/out/physics/spring_well.hpp ]]; then
  header=$work/out/physics/spring_well.hpp
  why=()
  grep -q 'struct SpringWell' "$header" || why+=("no struct SpringWell")
  grep -q 'T k, gamma;' "$header" || why+=("parameters not in the declared order (k, gamma)")
  grep -q 'omega\[0\] = sqrt(c.k);' "$header" || why+=("natural frequency not generated")
  grep -q '"spring_well"' "$work/out/physics/scene_catalog_data.cpp" || why+=("no catalog entry")
  printf '#include "physics/builtin_scenes.hpp"\nstatic_assert(cs::SpringWell::dof == 1 && cs::SpringWell::kz_constant);\n' >"$work/use.cpp"
  "$cxx" -std=c++20 -fsyntax-only -I"$src/src" -I"$work/out" "$work/use.cpp" 2>"$work/cc" || why+=("does not compile: $(head -3 "$work/cc")")
  if ((${#why[@]})); then echo "FAIL good header: ${why[*]}"; failed=$((failed + 1)); else echo "ok   good header"; passed=$((passed + 1)); fi
fi

# The real catalog generates.
check scenes.toml 0 "" "$src/src/physics/scenes.toml"

entry a "p^2/2 + k*q^2 - gamma*z" '{ name = "k", value = 2.0, description = "x" }' "$one_dof_vars" >"$work/f.toml"
check parameter_missing 1 "scene a: scene.K: K's parameters are {gamma, k}, not the {k} declared" "$work/f.toml"

entry b "p^2/2 + k*q^2 - gamma*z" "$k_params" '{ name = "q", value = 1.0, description = "x" }' >"$work/f.toml"
check variables_missing 1 "scene b: variables must be exactly those of K, z and lambda" "$work/f.toml"

entry c "p^2/2 + k*q^2 - gamma*z" "$k_params" "$one_dof_vars" 'natural_frequencies = ["sqrt(k*q)"]' >"$work/f.toml"
check frequency_reads_state 1 "scene c: scene.K: must not read a position or momentum" "$work/f.toml"

entry d "p^2/2 + k*q^2 - gamma*z" "$k_params" "$one_dof_vars" 'natural_frequencies = ["sqrt(m)"]' >"$work/f.toml"
check frequency_unknown_parameter 1 "reads m, which is not a parameter of K" "$work/f.toml"

entry e "p^2/2 + k*q^2 - gamma*z" "$k_params" "$one_dof_vars" 'label_rule = { rule = "nearest" }' >"$work/f.toml"
check label_rule_unknown 1 'label_rule.rule is "numbered" or "sign_of_q1", not "nearest"' "$work/f.toml"

entry f "p^2/2 + k*q^^2" "$k_params" "$one_dof_vars" >"$work/f.toml"
check bad_K 1 "scene f: scene.K:" "$work/f.toml"

entry G "p^2/2" "" "$one_dof_vars" >"$work/f.toml"
check bad_name 1 "scene G: a scene name is lower case letters, digits and '_'" "$work/f.toml"

printf '[[scene]]\nname = \n' >"$work/f.toml"
check toml_syntax 1 "(line 2)" "$work/f.toml"

echo "$passed passed, $failed failed"
((failed == 0))
