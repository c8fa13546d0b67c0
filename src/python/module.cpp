// contactsweep._core: the engine in the Python process (one process, no MPI). The package's
// __init__.py turns the spec into TOML text, names the output and loads the file into xarray;
// this file only runs cs::run (parallel/run_entry.hpp, the CLI's own entry) and maps its
// outcomes to Python: InputError -> ValueError with the CLI's message, Ctrl-C ->
// KeyboardInterrupt, anything else -> RuntimeError.
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "model/run_spec.hpp"
#include "numerics/method_catalog.hpp"
#include "parallel/run_entry.hpp"
#include "physics/scene_catalog.hpp"
#include "version.hpp"

namespace py = pybind11;

namespace {

// Runs with the interpreter released; the calling thread takes it back every 0.1 s (the tick)
// to check for signals (Ctrl-C) and to show progress. A KeyboardInterrupt raised there stops
// the run between blocks (run_entry.cpp) and is what Python sees.
void run(const std::string& spec_path, const std::optional<std::string>& spec_text,
         const std::vector<std::string>& overrides, const std::string& output, int threads,
         const std::optional<py::function>& progress, const std::string& history) {
  cs::RunArguments args;
  args.spec_path = spec_path;
  args.spec_text = spec_text;
  args.overrides = overrides;
  args.output = output;
  args.output_given = true;
  args.quiet = true;  // progress comes through the tick, not as lines on stderr
  args.command_line = history;
  args.threads = threads;
  args.tick = [&progress](double fraction) {
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (progress) (*progress)(fraction);
    return true;
  };
  try {
    const py::gil_scoped_release released;
    cs::run(args, MPI_COMM_NULL);
  } catch (const py::error_already_set&) {
    throw;
  } catch (...) {
    // A Ctrl-C that reached a child (the compiler of a K kernel) fails the run: say Ctrl-C.
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    throw;
  }
}

py::list scenes() {
  py::list out;
  for (const auto& s : cs::scene_catalog()) {
    py::list parameters, variables;
    for (const auto& p : s.parameters)
      parameters.append(py::dict(py::arg("name") = p.name, py::arg("default") = p.paper_value,
                                 py::arg("description") = p.description));
    for (const auto& v : s.variables)
      variables.append(py::dict(py::arg("name") = v.name, py::arg("default") = v.paper_value,
                                py::arg("description") = v.description));
    out.append(py::dict(py::arg("name") = s.name, py::arg("paper_label") = s.paper_label,
                        py::arg("hamiltonian") = s.hamiltonian, py::arg("dof") = s.dof,
                        py::arg("z_feeds_back") = s.z_feeds_back,
                        py::arg("parameters") = parameters, py::arg("variables") = variables,
                        py::arg("measures") = s.measures, py::arg("split_parts") = s.split_parts,
                        py::arg("default_h") = s.default_h,
                        py::arg("default_t_end") = s.default_t_end));
  }
  return out;
}

py::list methods() {
  py::list out;
  for (const auto& m : cs::method_catalog())
    out.append(py::dict(py::arg("name") = m.name, py::arg("order") = m.order,
                        py::arg("force_evaluations_per_step") = m.force_evaluations_per_step,
                        py::arg("properties") = m.properties,
                        py::arg("needs_split_parts") = m.needs_split_parts,
                        py::arg("adaptive") = m.adaptive));
  return out;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "contactsweep's engine in this process (see the package contactsweep)";
  m.attr("__version__") = cs::kVersion;
  py::register_local_exception_translator([](std::exception_ptr failure) {
    try {
      if (failure) std::rethrow_exception(failure);
    } catch (const cs::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const cs::Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    }
  });
  m.def("run", &run, py::arg("spec_path"), py::arg("spec_text"), py::arg("overrides"),
        py::arg("output"), py::arg("threads"), py::arg("progress"), py::arg("history"),
        "Runs a spec into the HDF5 file `output`, exactly as `contactsweep run` writes it.");
  m.def("scenes", &scenes, "The built-in scenes, as `contactsweep scenes` lists them.");
  m.def("methods", &methods, "The integrators, as `contactsweep methods` lists them.");
}
