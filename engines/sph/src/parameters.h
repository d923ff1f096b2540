// The parameters of a run in SI units: plain structs that the physics code takes. The deck parser (deck.h)
// fills them from the JSON deck and validates them; nothing here knows the deck's format.
#pragma once
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "eos.h"
#include "materials/solid_parameters.h"

namespace sph {

// Bad input: the message names the key, the value and what is allowed.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct MeshSpec {
  std::string name;
  std::string file, group;                   // HDF5 source (group holds vertices, faces) ...
  std::vector<std::vector<double>> vertices;  // ... or inline data
  std::vector<std::vector<long>> faces;
};

struct ProbeSpec {
  std::string name;
  std::vector<double> point;  // m
};

// A named patch of a plane: a disc (radius) or a rectangle (u, half_extents).
// In 2D it is a segment of half-length `radius` (or half_extents[0]).
struct PlanePatch {
  std::string name;
  std::vector<double> center, normal;  // m, unit vector
  double radius = 0.0;                 // m (disc)
  std::vector<double> u;               // in-plane direction (rectangle, 3D)
  std::vector<double> half_extents;    // m (rectangle)
};
using FlowPlaneSpec = PlanePatch;  // volume flux through it is measured

// Velocity inlet: fluid enters through the patch along `normal` at `velocity`,
// fed by `layers` layers of buffer particles behind the patch.
// profile: plug (velocity everywhere, the default), parabolic (disc: pipe
// Poiseuille; rectangle or 2D segment: plane Poiseuille across u) or annular
// (disc with inner_radius: the laminar annulus profile); for a profile,
// `velocity` is the mean speed over the patch. extrapolated: the buffer takes
// the mean density of the fluid just inside the patch (else its summation
// density). material: index into the run's materials (0 by default).
// ramp_time: the inlet's speed rises as 0.5 (1 - cos(pi t / ramp_time)) of
// its value up to t = ramp_time (0: full speed from the start), so that a
// scene filled at rest is not struck by the inflow (eq. OB4, open_boundaries.h).
struct InletSpec {
  PlanePatch patch;
  double velocity = 0.0;  // m/s
  int layers = 3;
  std::string profile = "plug";
  double inner_radius = 0.0;  // m (annular)
  bool extrapolated = false;
  int material = 0;
  double ramp_time = 0.0;  // s
};

// Outlet: fluid leaving through the patch along `normal` keeps its velocity
// in a buffer `layers` dx deep and is then removed. With `pressure` (Pa), the
// buffer holds the density of that pressure (the reference pressure of the
// domain); without it, each particle keeps the density it left with.
struct OutletSpec {
  PlanePatch patch;
  int layers = 3;
  std::optional<double> pressure;  // Pa
  bool backflow = false;           // a pressure opening: fluid may also enter through it (needs a pressure)
  double column_length = 0.0;      // m; > 0: a column outlet (outlet_buffer.h, eq. OB5; needs a pressure)
  double column_loss = 0.0;        // the column's loss coefficient K on its speed, -
  double column_area = 0.0;        // m^2 (m in 2D): the column's cross-section; 0: the patch's area
};

// One material of the deck's `materials` list. Every material is weakly
// compressible with a Tait EOS (rho0, c0, gamma, background_pressure, eq. 6);
// `model` names its constitutive model (material_models.h), which reads its
// own keys (Newtonian: `viscosity`, the kinematic viscosity of the Morris term).
struct MaterialSpec {
  std::string name, model = "newtonian";
  double rho0 = 0, c0 = 0, gamma = 7, background_pressure = 0;  // kg/m^3, m/s, -, Pa
  double viscosity = 0;                                         // kinematic, m^2/s (Newtonian)
  bool quadratic_eos = false;                                   // `eos`: "tait" (eq. 6) or "quadratic" (Nutto et al. eq. 9)
  std::optional<double> min_pressure;                           // cavitation floor of the pressure, Pa (eos.h)
  // PTT (materials/ptt.h): relaxation time s and viscosity Pa s per mode, extensibility, solvent viscosity Pa s
  std::vector<double> mode_lambda, mode_eta;
  double epsilon = 0, solvent_viscosity = 0;
  // PTT's plateau modulus G_p Pa and Cross solvent eta_0, eta_inf Pa s, K s, m - (eta_0 = 0: no Cross law)
  double storage_plateau = 0, cross_eta_0 = 0, cross_eta_inf = 0, cross_time = 0, cross_exponent = 0;
  double stress_diffusion = 0;  // PTT: diffusivity kappa of the mode stresses, m^2/s (eq. SD1; 0: none)
  SolidParameters solid;  // johnson_cook (materials/johnson_cook_material.h); c0 is then its wave speed
};

// A material's equation of state with its cavitation floor (eos.h).
inline TaitEos material_eos(const MaterialSpec& m) {
  TaitEos eos{m.rho0, m.c0, m.gamma, m.background_pressure, m.quadratic_eos};
  if (m.min_pressure) eos.set_min_pressure(*m.min_pressure);
  return eos;
}

// Lees-Edwards boundaries (box_policy.h): a sheared periodic cell, shear along
// x (axis 0), gradient along y (axis 1). Steady: gamma(t) = shear_rate t;
// oscillatory: gamma(t) = amplitude sin(omega t).
struct LeesEdwardsSpec {
  bool on = false;
  double shear_rate = 0;          // 1/s (steady)
  double amplitude = 0, omega = 0;  // strain amplitude, angular frequency rad/s (oscillatory)
  bool subtract_mean_stress = false;  // momentum takes sigma - <tau>, the cell's mean extra stress (simulation.h)
};

// A rigid impactor (impactors.h): an ideally hard body whose surface is a union of spheres, free or kinematic.
struct ImpactorSpec {
  std::string name;
  double mass = 0.0;                          // kg
  std::vector<double> inertia;                // about the centre of mass, world axes at the start, row-major 3 x 3, kg m^2
  std::vector<double> centre;                 // centre of mass, m
  std::vector<double> velocity, angular_velocity;  // m/s, rad/s (world)
  std::vector<std::vector<double>> spheres;   // x, y, z (m, world at the start) and radius (m) of each sphere
  double stiffness = 0.0;                     // contact spring k_c on a particle's overlap, N/m (eq. I1)
  bool kinematic = false;                     // prescribed velocity and angular velocity
};

// A rigid grain of particles that the fluid drags (grains.h): its particles are those of kind 4 (body) whose
// `grain` dataset names it.
struct GrainSpec {
  std::string name;
  double density = 0.0;                                // kg/m^3
  std::vector<double> velocity, angular_velocity;      // m/s, rad/s (world), initial
  std::vector<double> body_force;                      // m/s^2 on the grain (default: the deck's body force)
  double contact_radius = 0.0;                         // m: its sphere of grain-grain contact (0: none, eq. G6)
};

// Grain-grain contact (grains.h, eq. G6): a linear spring-dashpot along the line of centres, compression only.
struct GrainContactSpec {
  double stiffness = 0.0;    // k, N/m (0: no contact)
  double solid_stiffness = 0.0;  // k_s, N/m: a grain's sphere on each solid particle (eq. G8; 0: none)
  double restitution = 1.0;  // e, normal coefficient of restitution, 0 < e <= 1
  std::vector<std::array<double, 6>> walls;  // planes the grains touch (eq. G7): a point (m), a unit normal into the fluid
};

// Every setting of a run (what the deck parser returns).
struct RunParameters {
  int dimension = 3;
  std::string particles_file;
  unsigned terms = 0;  // bit set of term:: flags
  // materials: empty means one Newtonian material from the top-level keys below
  // (every deck written before materials existed); otherwise the top-level
  // rho0, c0, gamma, background_pressure hold those of materials[0] (inlets use them).
  std::vector<MaterialSpec> materials;
  // fluid
  double rho0 = 0, c0 = 0, gamma = 7, background_pressure = 0;  // kg/m^3, m/s, -, Pa
  std::optional<double> min_pressure;                           // one material: its cavitation floor, Pa
  double v_max = 0;                                             // expected max speed, m/s
  double viscosity = 0;                                         // kinematic, m^2/s
  double alpha = 0, beta = 0;                                   // artificial viscosity
  bool av_walls = true;  // artificial viscosity also on pairs with a fixed particle
  double density_diffusion = 0;  // delta of eq. DD1 (physics_terms.h): density diffusion between fluid particles
  bool viscosity_correction = false;  // Morris sum renormalised per particle (viscosity_correction.h, eq. VC1)
  double smagorinsky_cs = 0;  // > 0: Smagorinsky's eddy viscosity nu_t = (cs dx)^2 |S| (eddy_viscosity.h, eq. SM1)
  bool eddy_walls = true;     // nu_t also on pairs with a fixed particle (false: fluid-fluid pairs only, eq. SM2)
  double h = 0, dx = 0;                                         // m
  std::vector<double> body_force;                               // m/s^2
  bool body_force_solids = true;  // false: the body force acts on the fluids' particles only (not on solids)
  // walls
  std::vector<MeshSpec> meshes;
  double wall_range = 0, wall_s = 0, wall_psi = 0;  // R m, s m, psi N
  std::vector<ImpactorSpec> impactors;               // rigid impactors (3D)
  std::vector<GrainSpec> grains;                     // rigid grains of particles (3D)
  GrainContactSpec grain_contact;                    // their contact with each other (eq. G6)
  // periodic boundaries
  LeesEdwardsSpec lees_edwards;
  std::vector<int> periodic_axes;
  std::vector<double> periodic_lo, periodic_hi;  // m, one per axis
  // open boundaries
  std::vector<InletSpec> inlets;
  std::vector<OutletSpec> outlets;
  // time
  std::optional<double> dt;                                  // fixed step, s
  double cfl = 0.25, viscous_factor = 0.125, force_factor = 0.25;
  double t_end = 0;                                          // s
  long max_steps = 0;                                        // 0: no limit
  // resumed run (the particle file holds a stopped run's last frame): its time and step, s
  double t_start = 0;
  long step_start = 0;
  // stability
  double max_density_deviation = 0.1;  // |rho/rho0 - 1| allowed
  // output
  std::string output_file = "out.h5";
  double frame_interval = 0, series_interval = 0;  // s
  std::vector<ProbeSpec> probes;
  std::vector<FlowPlaneSpec> flow_planes;
  double progress_interval = 1.0;  // s of wall time
  int threads = 0;                 // 0: OpenMP default
  // Verlet skin as a fraction of the support 2h (LAMMPS's 0.3 mm on a 3 mm cutoff is 0.1): the list
  // holds pairs closer than (1 + skin) 2h and is rebuilt when a particle has moved skin/2 since the build.
  double neighbour_skin = 0.1;
  // Open boundaries' conversions: "kept" re-sorts the list's rows and lets additions and removals wait
  // for the next build where that is exact (open_boundaries.h); "rebuilt" rebuilds the list at each change.
  std::string open_boundary_list = "kept";

  std::string terms_string() const;
  bool inlets_extrapolated() const;  // there are inlets and every one extrapolates its pressure
  // The run's materials: `materials`, or the one Newtonian material of the top-level keys.
  std::vector<MaterialSpec> material_list() const;
};

}  // namespace sph
