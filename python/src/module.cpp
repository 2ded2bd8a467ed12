// The `dipc._dipc` extension: dipc::Simulation (src/app/simulation.hpp) for Python. The
// `dipc` package (python/dipc/__init__.py) re-exports it; docs/python.md is its manual.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <mpi.h>
#include <petscvec.h>

#include <algorithm>
#include <array>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/checked_run_options.hpp"
#include "app/petsc_input_errors.hpp"
#include "app/problem_builder.hpp"
#include "app/simulation.hpp"
#include "io/scene.hpp"
#include "petsc_session.hpp"

namespace py = pybind11;

namespace dipc::python {
namespace {

// Python's exception classes (made in the module's init): Error for solver failures, InputError
// (also a ValueError) for bad scenes and options, StepFailure for a step that step recovery
// could not take (fatal: an invariant was violated).
PyObject* error_type = nullptr;
PyObject* input_error_type = nullptr;
PyObject* step_failure_type = nullptr;

[[noreturn]] void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

// A solver call: a PETSc error code or an input error thrown by dipc becomes a Python
// exception with dipc's message, the same on every rank for input errors (they are collective).
template <class F>
void call(F&& f) {
  PetscErrorCode code = 0;
  try {
    code = f();
  } catch (const py::error_already_set&) {
    throw;
  } catch (const std::exception& e) {
    raise(input_error_type, e.what());
  }
  if (code == PETSC_ERR_USER_INPUT) raise(input_error_type, last_petsc_error_message());
  if (code) raise(error_type, "PETSc error " + std::to_string(code) + ": " + last_petsc_error_message());
}

MPI_Comm communicator(const py::object& comm) {
  if (comm.is_none()) return PETSC_COMM_WORLD;
  // An mpi4py communicator, through its Fortran handle (no build dependency on mpi4py).
  if (!py::hasattr(comm, "py2f")) raise(PyExc_TypeError, "comm must be an mpi4py communicator or None");
  return MPI_Comm_f2c(comm.attr("py2f")().cast<MPI_Fint>());
}

Scene read_scene(const py::object& scene) {
  if (scene.is_none()) return default_scene();
  if (py::isinstance<py::dict>(scene)) {
    const std::string text = py::module_::import("json").attr("dumps")(scene).cast<std::string>();
    const std::string cwd = py::module_::import("os").attr("getcwd")().cast<std::string>();
    return parse_scene_text(text, "<scene dict>", cwd);
  }
  // A path (str or os.PathLike): dipc's scene format or PolyFEM's.
  return parse_scene_file(py::module_::import("os").attr("fspath")(scene).cast<std::string>());
}

py::dict report_dict(const StepReport& r) {
  py::dict d;
  d["step"] = r.step;
  d["time"] = r.time;
  d["dt"] = r.dt;
  d["substeps"] = r.substeps;
  d["dt_cuts"] = r.dt_cuts;
  d["newton_iterations"] = r.newton.iterations;
  d["linear_iterations"] = r.newton.linear_iterations;
  d["converged_by"] = r.newton.ended_by;
  d["alpha_min"] = r.newton.min_alpha;
  d["energy"] = r.energy;
  d["min_volume_ratio"] = r.min_volume_ratio;
  d["wall_seconds"] = r.wall_seconds;
  d["linear_solve_seconds"] = r.linear_solve_seconds;
  d["contact_pairs"] = r.contact_pairs;
  d["min_distance"] = r.min_distance;
  d["kappa"] = r.kappa;
  d["alpha_ccd"] = r.alpha_ccd;
  d["contact_seconds"] = r.broad_phase_seconds + r.ccd_seconds + r.barrier_seconds + r.exchange_seconds;
  return d;
}

py::dict result_dict(const RunResult& r) {
  py::dict d;
  d["steps_taken"] = r.steps_taken;
  d["newton_iterations"] = r.newton_iterations;
  d["linear_iterations"] = r.linear_iterations;
  d["dt_cuts"] = r.dt_cuts;
  d["max_contact_pairs"] = r.max_contact_pairs;
  d["num_elements"] = r.num_elements;
  d["num_dofs"] = r.num_dofs;
  d["xdmf_path"] = r.xdmf_path;
  d["checkpoint_path"] = r.checkpoint_path;
  d["failure"] = r.failure;
  const PhaseTimes& t = r.times;
  d["seconds"] = py::dict(py::arg("partition") = t.partition, py::arg("setup") = t.setup,
                          py::arg("assembly") = t.assembly, py::arg("line_search") = t.line_search,
                          py::arg("contact") = t.contact, py::arg("contact_patterns") = t.preallocation,
                          py::arg("linear_solve") = t.linear_solve, py::arg("output") = t.output,
                          py::arg("other") = t.other, py::arg("total") = t.total);
  return d;
}

py::array_t<double> nodes_by_3(std::vector<double>&& values) {
  auto* owned = new std::vector<double>(std::move(values));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  const py::ssize_t n = static_cast<py::ssize_t>(owned->size() / 3);
  return py::array_t<double>({n, py::ssize_t(3)}, owned->data(), free);
}

// The live simulations, closed before PETSc is finalised at interpreter exit.
class PySimulation;
std::set<PySimulation*>& live() {
  static std::set<PySimulation*> s;
  return s;
}

class PySimulation {
 public:
  PySimulation(const py::object& scene, const std::vector<std::string>& options, const py::object& comm,
               bool report) {
    initialize_petsc();
    comm_ = communicator(comm);
    Scene parsed;
    call([&] {
      parsed = read_scene(scene);
      return PetscErrorCode(0);
    });
    call([&] {
      database_ = std::make_unique<OptionsDatabase>(comm_, options);
      return PetscErrorCode(0);
    });
    OptionsScope scope(*database_);
    call([&] {
      RunOptions run_options;
      PetscCall(checked_run_options(comm_, parsed, &run_options));
      run_options.report = report;  // the run header and timing table
      for (const std::string& note : parsed.notes)
        PetscCall(PetscPrintf(comm_, "dipc: PolyFEM scene: %s\n", note.c_str()));
      return Simulation::create(parsed, comm_, run_options, &simulation_);
    });
    live().insert(this);
  }
  ~PySimulation() { close(); }

  // Frees the solver (collective); the object answers nothing afterwards.
  void close() {
    live().erase(this);
    if (!simulation_) return;
    if (petsc_finalized()) {
      (void)simulation_.release();  // PETSc is gone: nothing may be destroyed through it
      (void)database_.release();
      return;
    }
    {
      OptionsScope scope(*database_);
      simulation_.reset();
    }
    database_.reset();
  }

  // One scene step; None once the run has ended (its last step taken, or a stop signal).
  py::object step() {
    Simulation& s = open();
    if (s.ended()) return py::none();
    StepReport report;
    {
      OptionsScope scope(*database_);
      call([&] { return s.step(&report); });
    }
    raise_on_failure();
    if (report.step == 0) return py::none();
    return report_dict(report);
  }

  // The remaining steps, then finish(): the run's totals.
  py::dict run() {
    while (!open().ended()) step();
    return finish();
  }

  py::dict finish() {
    Simulation& s = open();
    if (finished_) raise(error_type, "finish: the run has already finished");
    RunResult result;
    {
      OptionsScope scope(*database_);
      call([&] { return s.finish(&result); });
    }
    finished_ = true;
    raise_on_failure();
    return result_dict(result);
  }

  // Owned-node fields, (owned nodes, 3), rows in the order of node_ids().
  py::array_t<double> positions() { return owned_field(open().integrator().positions()); }
  py::array_t<double> velocities() { return owned_field(open().integrator().velocities()); }
  py::array_t<double> reference_positions() { return owned_field(open().integrator().reference_positions()); }
  py::array_t<double> contact_forces() { return forces(false); }
  py::array_t<double> friction_forces() { return forces(true); }
  py::array_t<std::int64_t> node_ids() {
    const DistributedMesh& mesh = open().mesh();
    py::array_t<std::int64_t> ids(mesh.num_owned_nodes);
    std::copy(mesh.node_input_id.begin(), mesh.node_input_id.begin() + mesh.num_owned_nodes, ids.mutable_data());
    return ids;
  }

  // The mesh's named node sets (a body's name: all its nodes; "beam.xmin" and the like; a
  // mesh file's physical groups) as rows of this rank's owned fields.
  py::dict node_sets() {
    const DistributedMesh& mesh = open().mesh();
    py::dict sets;
    for (const auto& [name, members] : mesh.node_sets) {
      std::vector<std::int64_t> rows;
      for (std::int32_t l : members)
        if (l < mesh.num_owned_nodes) rows.push_back(l);
      std::sort(rows.begin(), rows.end());
      sets[py::str(name)] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(rows.size()), rows.data());
    }
    return sets;
  }

  // A node field of every rank on rank 0, (input nodes, 3) in the input numbering; None on the
  // other ranks. Collective.
  py::object gather(const std::string& name) {
    Simulation& s = open();
    Vec field = nullptr, made = nullptr;
    TimeIntegrator& integrator = s.integrator();
    if (name == "positions") field = integrator.positions();
    else if (name == "velocities") field = integrator.velocities();
    else if (name == "reference_positions") field = integrator.reference_positions();
    else if (name == "contact_forces" || name == "friction_forces") {
      call([&] { return force_vector(name == "friction_forces", &made); });
      field = made;
    } else {
      raise(PyExc_KeyError, "gather: unknown field \"" + name +
                                "\" (positions, velocities, reference_positions, contact_forces, friction_forces)");
    }
    std::vector<double> all;
    call([&] { return gather_by_input_id(s.mesh(), field, &all); });
    if (made) VecDestroy(&made);
    int rank;
    MPI_Comm_rank(comm_, &rank);
    if (rank != 0) return py::none();
    return nodes_by_3(std::move(all));
  }

  // The prescribed node sets: the scene's Dirichlet conditions, then its kinematic bodies.
  py::list prescribed_sets() {
    const Scene& scene = open().scene();
    py::list sets;
    for (std::size_t k = 0; k < scene.dirichlet.size(); ++k) {
      const DirichletCondition& bc = scene.dirichlet[k];
      sets.append(py::dict(py::arg("index") = k, py::arg("key") = bc.key_path, py::arg("name") = bc.selection.name,
                           py::arg("selection") = bc.selection.describe()));
    }
    return sets;
  }

  // A new motion (a scene motion as a dict) for one prescribed set, named by index, key path or
  // selection, from its current positions on (TimeIntegrator::set_prescribed_motion).
  void set_motion(const py::object& key, const py::dict& motion) {
    Simulation& s = open();
    const int k = set_index(s.scene(), key);
    const std::string text = py::module_::import("json").attr("dumps")(motion).cast<std::string>();
    OptionsScope scope(*database_);
    call([&] {
      const Motion parsed = parse_motion_text(text, "set_motion(" + s.scene().dirichlet[k].key_path + ")");
      return s.integrator().set_prescribed_motion(k, prescribed_motion(parsed));
    });
  }

  double time() { return open().integrator().time(); }
  int steps_taken() { return open().steps_taken(); }
  int last_step() { return open().last_step(); }
  bool ended() { return open().ended(); }
  std::string xdmf_path() { return open().progress().xdmf_path; }

 private:
  Simulation& open() {
    if (!simulation_) raise(error_type, "this Simulation is closed");
    return *simulation_;
  }

  void raise_on_failure() {
    const RunResult& r = open().progress();
    if (r.failure.empty() || failure_raised_) return;
    failure_raised_ = true;  // once: finish() may still be called for the timing table
    py::object error = py::reinterpret_borrow<py::object>(step_failure_type)(r.failure);
    error.attr("fatal") = r.fatal;
    PyErr_SetObject(step_failure_type, error.ptr());
    throw py::error_already_set();
  }

  // A host vector's owned values are shown in place (read-only; they follow the state, so a
  // step's values are kept with .copy()); a device vector's are copied once to the host.
  py::array_t<double> owned_field(Vec v) {
    PetscBool host = PETSC_FALSE;
    call([&] { return PetscObjectTypeCompareAny((PetscObject)v, &host, VECSEQ, VECMPI, VECSTANDARD, ""); });
    if (!host) return nodes_by_3(local_values(v));
    PetscInt n = 0;
    const PetscScalar* a = nullptr;
    call([&] {
      PetscCall(VecGetLocalSize(v, &n));
      return VecGetArrayRead(v, &a);
    });
    // The array keeps its vector alive (a reference, given back when NumPy frees the array).
    PetscObjectReference((PetscObject)v);
    py::capsule keep(v, [](void* p) {
      Vec vec = static_cast<Vec>(p);
      if (!petsc_finalized()) VecDestroy(&vec);
    });
    py::array_t<double> out({py::ssize_t(n / 3), py::ssize_t(3)}, a, keep);
    py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    call([&] { return VecRestoreArrayRead(v, &a); });
    return out;
  }

  // A copy of v's local values on the host (one copy from a device vector).
  std::vector<double> local_values(Vec v) {
    PetscInt n = 0;
    const PetscScalar* a = nullptr;
    call([&] {
      PetscCall(VecGetLocalSize(v, &n));
      return VecGetArrayRead(v, &a);
    });
    std::vector<double> values(a, a + n);
    call([&] { return VecRestoreArrayRead(v, &a); });
    return values;
  }

  // Collective: the barrier's or friction's force on each owned node (zero without that term).
  PetscErrorCode force_vector(bool friction, Vec* out) {
    PetscFunctionBeginUser;
    TimeIntegrator& integrator = open().integrator();
    PetscCall(VecDuplicate(integrator.positions(), out));
    PetscCall(VecSet(*out, 0.0));
    if (!integrator.contact()) PetscFunctionReturn(0);
    Vec other = nullptr;
    PetscCall(VecDuplicate(*out, &other));
    std::array<long, ContactForm::num_pair_kinds> pairs{};
    OptionsScope scope(*database_);
    PetscCall(integrator.contact_forces(friction ? other : *out, friction ? *out : nullptr, &pairs));
    PetscCall(VecDestroy(&other));
    PetscFunctionReturn(0);
  }

  py::array_t<double> forces(bool friction) {
    Vec v = nullptr;
    call([&] { return force_vector(friction, &v); });
    std::vector<double> values = local_values(v);
    call([&] { return VecDestroy(&v); });
    return nodes_by_3(std::move(values));
  }

  static int set_index(const Scene& scene, const py::object& key) {
    const int count = static_cast<int>(scene.dirichlet.size());
    if (py::isinstance<py::int_>(key)) {
      const int k = key.cast<int>();
      if (k < 0 || k >= count)
        raise(PyExc_IndexError, "set_motion: no prescribed set " + std::to_string(k) + " (the scene has " +
                                    std::to_string(count) + ")");
      return k;
    }
    const std::string name = py::str(key).cast<std::string>();
    int found = -1;
    std::string names;
    for (int k = 0; k < count; ++k) {
      const DirichletCondition& bc = scene.dirichlet[k];
      names += (k ? ", " : "") + bc.key_path + (bc.selection.name.empty() ? "" : " (\"" + bc.selection.name + "\")");
      if (bc.key_path != name && bc.selection.name != name) continue;
      if (found >= 0) raise(PyExc_KeyError, "set_motion: \"" + name + "\" names several prescribed sets; give the index");
      found = k;
    }
    if (found < 0) raise(PyExc_KeyError, "set_motion: no prescribed set \"" + name + "\" (sets: " + names + ")");
    return found;
  }

  MPI_Comm comm_ = MPI_COMM_NULL;
  std::unique_ptr<OptionsDatabase> database_;
  std::unique_ptr<Simulation> simulation_;
  bool finished_ = false, failure_raised_ = false;
};

// At interpreter exit (registered by the package): every live Simulation closed, then PETSc.
void shutdown() {
  const std::set<PySimulation*> open = live();
  for (PySimulation* s : open) s->close();
  finalize_petsc();
}

PyObject* new_exception(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  PyObject* type = PyErr_NewExceptionWithDoc((std::string("dipc.") + name).c_str(), doc, bases, nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

}  // namespace
}  // namespace dipc::python

PYBIND11_MODULE(_dipc, m) {
  using namespace dipc::python;
  m.doc() = "dipc's solver (the dipc package re-exports it; see docs/python.md)";
  error_type = new_exception(m, "Error", PyExc_RuntimeError, "A dipc solver error (PETSc's message).");
  const py::tuple input_error_bases = py::make_tuple(py::handle(error_type), py::handle(PyExc_ValueError));
  input_error_type = new_exception(m, "InputError", input_error_bases.ptr(),
                                   "Bad input: a scene, option or value dipc refuses (its message names it).");
  step_failure_type = new_exception(m, "StepFailure", error_type,
                                    "A step that step recovery could not take; .fatal: an invariant was violated.");
  m.def("shutdown", &shutdown, "Close every Simulation and finalise PETSc; registered with atexit by `import dipc`.");
  py::class_<PySimulation>(m, "Simulation")
      .def(py::init<const py::object&, const std::vector<std::string>&, const py::object&, bool>(),
           py::arg("scene") = py::none(), py::arg("options") = std::vector<std::string>(), py::arg("comm") = py::none(),
           py::kw_only(), py::arg("report") = true)
      .def("step", &PySimulation::step)
      .def("run", &PySimulation::run)
      .def("finish", &PySimulation::finish)
      .def("close", &PySimulation::close)
      .def("positions", &PySimulation::positions)
      .def("velocities", &PySimulation::velocities)
      .def("reference_positions", &PySimulation::reference_positions)
      .def("contact_forces", &PySimulation::contact_forces)
      .def("friction_forces", &PySimulation::friction_forces)
      .def("node_ids", &PySimulation::node_ids)
      .def("node_sets", &PySimulation::node_sets)
      .def("gather", &PySimulation::gather, py::arg("field"))
      .def("prescribed_sets", &PySimulation::prescribed_sets)
      .def("set_motion", &PySimulation::set_motion, py::arg("set"), py::arg("motion"))
      .def_property_readonly("time", &PySimulation::time)
      .def_property_readonly("steps_taken", &PySimulation::steps_taken)
      .def_property_readonly("last_step", &PySimulation::last_step)
      .def_property_readonly("ended", &PySimulation::ended)
      .def_property_readonly("xdmf_path", &PySimulation::xdmf_path);
}
