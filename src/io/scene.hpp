// Scene: the physics of a run as read from a JSON scene file (numerics live in PETSc
// options). Every field is validated by parse_scene(); see scene_parser.cpp for the keys.
#pragma once
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dipc {

struct Material {
  std::string name;
  double E = 1e6;     // Young's modulus [Pa], > 0
  double nu = 0.3;    // Poisson ratio, in (-1, 0.5)
  double rho = 1000;  // density [kg/m^3], > 0
  // "volumetric": where the volumetric term lambda/2 (ln J)^2 is evaluated: at the Gauss points
  // (default, the standard element) or on each element's mean volume ratio ("mean_dilatation",
  // locking-free for nearly incompressible materials; assembly/hex8_mean_dilatation.hpp).
  bool mean_dilatation = false;
  // "model": the hyperelastic energy, "neo_hookean" (default) or "stable_neo_hookean" (Smith,
  // de Goes & Kim 2018; assembly/stable_neo_hookean.hpp). Both take E and nu as the Lame
  // parameters of their linearisation. The app maps it to assembly's MaterialModel.
  enum class Model { neo_hookean, stable_neo_hookean };
  Model model = Model::neo_hookean;
};

// A box of hexahedra: `size` edge lengths, `resolution` elements per edge, min corner at `origin`.
struct BoxGenerator {
  std::array<double, 3> size{1, 1, 1};
  std::array<int, 3> resolution{1, 1, 1};
  std::array<double, 3> origin{0, 0, 0};
};

// Boundary faces that a PolyFEM surface selection gives an id (io/polyfem_scene.cpp): every
// boundary face of the body, or those whose centroid lies in `box` (inclusive); a face takes the
// id of the first selection that holds it. The mesh builder turns each id into the node set
// "<body>.surface_selection_<id>" (the nodes of its faces).
struct FaceSelection {
  int id = 0;
  std::optional<std::array<double, 6>> box;  // xmin ymin zmin xmax ymax zmax; none: every face
};

struct Body {
  std::string name;                            // used to prefix generated selections ("beam.xmin")
  std::string mesh_file;                       // Gmsh MSH 4.1/2.2 (resolved relative to the scene file), or
  std::optional<BoxGenerator> box;             // a generated box (exactly one of the two)
  std::array<double, 3> translation{0, 0, 0};  // applied to a mesh file's coordinates
  double scale = 1.0;                          // applied before the translation
  // A linear map applied first (row-major): x = scale·(linear·X) + translation. The identity
  // in dipc's own format; PolyFEM's `transformation` gives rotation · diag(scale).
  std::array<double, 9> linear{1, 0, 0, 0, 1, 0, 0, 0, 1};
  // PolyFEM's transformation.dimensions (Gmsh bodies only): bounding-box sizes that scale the
  // file's points axis by axis before `linear` (io/bounding_box_scale.hpp).
  std::optional<std::array<double, 3>> dimensions;
  std::vector<FaceSelection> face_selections;  // PolyFEM surface selections, in priority order
  std::size_t material = 0;                    // index into Scene::materials
  std::array<double, 3> initial_velocity{0, 0, 0};
  // Initial spin: the velocity at X is initial_velocity + ω × (X − center).
  std::array<double, 3> initial_angular_velocity{0, 0, 0}, spin_center{0, 0, 0};
  bool self_contact = true;  // contact between this body's own surface primitives
  // Prescribed entirely (rollers, presses): the parser turns its "kinematic" motion into a
  // DirichletCondition on all its nodes (selection = name), appended to Scene::dirichlet.
  bool kinematic = false;
};

// Which nodes a boundary condition acts on: a named node set of the mesh, or all nodes
// inside an axis-aligned box (inclusive, with a tolerance of 1e-9 x the scene diagonal).
struct Selection {
  std::string name;                          // named set, or empty
  std::optional<std::array<double, 6>> box;  // xmin ymin zmin xmax ymax zmax
  std::string describe() const;              // for messages
};

// A prescribed motion as the scene gives it (Dirichlet conditions, kinematic bodies, obstacles).
struct Motion {
  enum class Kind { Fixed, Velocity, Rotation, Path };
  Kind kind = Kind::Fixed;
  std::array<double, 3> velocity{0, 0, 0};  // Velocity: x(t) = X + v t
  std::array<double, 3> axis{0, 0, 1};      // Rotation: about `axis` (normalised) through
  std::array<double, 3> center{0, 0, 0};    //   `center` at `angular_velocity` [rad/s]
  double angular_velocity = 0;
  // Path: x(t) = X + d(t), piecewise linear through keyframes (t, dx, dy, dz); the first is
  // (0, 0, 0, 0), times strictly increase, d is held after the last.
  std::vector<std::array<double, 4>> path;
};

struct DirichletCondition : Motion {
  Selection selection;
  std::string key_path;  // e.g. "boundary_conditions.dirichlet[0]"
};

// A half-space obstacle: the solid occupies {x : (x - point)·normal < 0}, bodies stay on the
// side the normal points to. `normal` is normalised by the parser.
struct Plane {
  std::array<double, 3> point{0, 0, 0};
  std::array<double, 3> normal{0, 0, 1};
};

// A triangle-mesh obstacle (OBJ or STL, open or closed): a contact surface whose positions are
// prescribed functions of time, never unknowns. Vertices are placed as
// x = scale·(linear·diag(f)·X_file) + translation at t = 0 (f from `dimensions`, else 1) and
// then follow `motion`.
struct Obstacle {
  std::string name;       // for messages; defaults to "obstacle<i>"
  std::string mesh_file;  // resolved relative to the scene file
  double scale = 1.0;
  std::array<double, 3> translation{0, 0, 0};
  std::array<double, 9> linear{1, 0, 0, 0, 1, 0, 0, 0, 1};  // x = scale·(linear·X) + translation
  // PolyFEM's transformation.dimensions, as Body::dimensions; 0 only along a flat axis.
  std::optional<std::array<double, 3>> dimensions;
  Motion motion;
  std::string key_path;  // "contact.obstacles[0]"
};

struct ContactSettings {
  bool enabled = false;
  // Activation DISTANCE d̂ in length units, NOT squared (the contact point functions use its
  // square, as IPC Toolkit does). With dhat_relative, d̂ = dhat × the diagonal of the
  // bounding box of all bodies' rest positions (dhat then in (0, 1)).
  double dhat = 1e-3;
  bool dhat_relative = true;
  bool kappa_adaptive = true;       // adaptive barrier stiffness (Li et al. 2020, IPC)
  double kappa = 0;                 // the fixed barrier stiffness κ when !kappa_adaptive (> 0)
  double friction = 0.0;            // Coulomb coefficient μ (no friction form when 0)
  double epsv = 1e-3;               // friction smoothing velocity ε_v [m/s]
  int friction_iterations = 1;      // lagged friction updates per time step, >= 1
  std::vector<Plane> planes;        // analytic obstacles
  std::vector<Obstacle> obstacles;  // triangle-mesh obstacles
};

struct Scene {
  std::string source;  // file path, or "<default scene>"
  std::vector<Material> materials;
  std::vector<Body> bodies;
  std::array<double, 3> gravity{0, 0, 0};
  std::vector<DirichletCondition> dirichlet;
  // time
  bool is_static = false;  // "integrator": "static": load steps minimising elastic + body energy
  double dt = 0.01;
  int steps = 1;
  // mass
  bool lumped_mass = true;
  // output
  std::string output_directory = "output";
  std::string output_name = "dipc";
  int output_every = 1;  // write every N-th step (the last step is always written)
  ContactSettings contact;
  // Lines for rank 0 to print before the run: what a scene in PolyFEM's format held that dipc
  // ignores or reads differently (io/polyfem_scene.cpp); empty for dipc's own format.
  std::vector<std::string> notes;
};

// Parses and validates a scene. On any problem throws SceneError whose message names the
// file and the key path ("scene.json: materials[0].nu = 0.5 must be in (-1, 0.5)").
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Either format: dipc's own (scene_parser.cpp) or PolyFEM's (polyfem_scene.cpp), told apart
// by is_polyfem_scene().
Scene parse_scene_file(const std::string& path);
Scene parse_scene_text(const std::string& json_text, const std::string& source_name, const std::string& base_directory);
// A prescribed motion alone, as a scene gives it ({"type": "velocity", "velocity": [...]}, ...);
// errors as parse_scene_text's, under `source_name`.
Motion parse_motion_text(const std::string& json_text, const std::string& source_name);
// The scene embedded in the program, used when no scene file is given: a soft box dropped
// onto a wider box that rests on a ground plane (contact with friction).
Scene default_scene();
// The previous default: a cantilever beam clamped at x = 0 sagging under gravity, no contact
// (also scenes/default_beam.json); elastodynamics tests use it.
Scene beam_scene();

}  // namespace dipc
