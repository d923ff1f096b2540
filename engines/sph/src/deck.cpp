#include "deck.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "deck_json.h"
#include "physics_terms.h"

namespace sph {
namespace {

using namespace deck_json;

// A path of the deck, relative to the deck file's folder `deck_dir` unless absolute.
std::string resolve(const std::string& deck_dir, const std::string& path) {
  const std::filesystem::path p(path);
  return p.is_absolute() || deck_dir.empty() ? p.string() : (std::filesystem::path(deck_dir) / p).string();
}

unsigned parse_physics(const json& v) {
  std::vector<std::string> names;
  for (const auto& t : term::optional) names.push_back(t.name);
  if (!v.is_array()) fail("'physics' must be a list of term names from: " + join(names));
  unsigned bits = 0;
  for (const auto& item : v) {
    if (!item.is_string()) fail("'physics' entries must be strings from: " + join(names));
    const auto s = item.get<std::string>();
    const auto* t = std::find_if(std::begin(term::optional), std::end(term::optional),
                                 [&](const term::Named& n) { return s == n.name; });
    if (t == std::end(term::optional))
      fail("unknown physics term '" + s + "'; allowed: " + join(names) +
           " (continuity, Tait EOS and pressure gradient are always on)");
    bits |= t->bit;
  }
  return bits;
}

// A key that belongs to a term must be present exactly when the term is on.
void require_with_term(const json& j, const RunParameters& d, unsigned bit, const std::string& key, const std::string& term) {
  const bool on = d.terms & bit;
  if (on && !j.contains(key)) fail("physics term '" + term + "' is on but key '" + key + "' is missing");
  if (!on && j.contains(key)) fail("key '" + key + "' is given but physics term '" + term + "' is not in 'physics'");
}

void parse_meshes(const json& j, const std::string& deck_dir, RunParameters& d) {
  if (!j.is_array() || j.empty()) fail("'meshes' must be a non-empty list");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = "meshes[" + std::to_string(i) + "]";
    check_keys(j[i], path, {"name", "file", "group", "vertices", "faces"});
    MeshSpec m;
    m.name = unique_name(j[i], path, seen);
    if (j[i].contains("file")) {
      if (j[i].contains("vertices") || j[i].contains("faces"))
        fail("'" + path + "' has both 'file' and inline 'vertices'/'faces'; give one");
      m.file = resolve(deck_dir, text(j[i]["file"], where(path, "file")));
      if (!std::filesystem::exists(m.file)) fail("mesh file '" + m.file + "' (" + path + ".file) does not exist");
      m.group = j[i].contains("group") ? text(j[i]["group"], where(path, "group")) : "/";
    } else {
      const auto& v = need(j[i], path, "vertices");
      const auto& f = need(j[i], path, "faces");
      if (!v.is_array() || v.empty() || !f.is_array() || f.empty())
        fail("'" + path + ".vertices' and '.faces' must be non-empty lists");
      for (std::size_t k = 0; k < v.size(); ++k)
        m.vertices.push_back(vector_of(v[k], path + ".vertices[" + std::to_string(k) + "]", d.dimension));
      for (std::size_t k = 0; k < f.size(); ++k) {
        const auto name = path + ".faces[" + std::to_string(k) + "]";
        if (!f[k].is_array() || f[k].size() != static_cast<std::size_t>(d.dimension))
          fail("'" + name + "' must list " + std::to_string(d.dimension) + " vertex indices");
        std::vector<long> face;
        for (const auto& x : f[k]) {
          if (!x.is_number_integer()) fail("'" + name + "' must hold integers");
          face.push_back(x.get<long>());
        }
        m.faces.push_back(face);
      }
    }
    d.meshes.push_back(std::move(m));
  }
}

void parse_output(const json& j, const std::string& deck_dir, RunParameters& d) {
  const std::string p = "output";
  check_keys(j, p, {"file", "frame_interval", "series_interval", "probes", "flow_planes", "progress_interval"});
  if (j.contains("file")) d.output_file = resolve(deck_dir, text(j["file"], "output.file"));
  else d.output_file = resolve(deck_dir, d.output_file);
  d.frame_interval = positive(j, p, "frame_interval");
  d.series_interval = j.contains("series_interval") ? positive(j, p, "series_interval") : d.frame_interval;
  if (j.contains("progress_interval")) d.progress_interval = positive(j, p, "progress_interval");
  std::set<std::string> seen;
  if (j.contains("probes")) {
    if (!j["probes"].is_array()) fail("'output.probes' must be a list");
    for (std::size_t i = 0; i < j["probes"].size(); ++i) {
      const std::string path = "output.probes[" + std::to_string(i) + "]";
      const auto& e = j["probes"][i];
      check_keys(e, path, {"name", "point"});
      d.probes.push_back({unique_name(e, path, seen), vector_of(need(e, path, "point"), path + ".point", d.dimension)});
    }
  }
  seen.clear();
  if (j.contains("flow_planes")) {
    if (!j["flow_planes"].is_array()) fail("'output.flow_planes' must be a list");
    for (std::size_t i = 0; i < j["flow_planes"].size(); ++i) {
      const std::string path = "output.flow_planes[" + std::to_string(i) + "]";
      const auto& e = j["flow_planes"][i];
      check_keys(e, path, {"name", "center", "normal", "radius", "u", "half_extents"});
      d.flow_planes.push_back(parse_patch(e, path, d.dimension, seen));
    }
  }
}

// `eddy_viscosity`: {"model": "smagorinsky", "cs": C, "walls": true} (eddy_viscosity.h); the scalar path of one fluid with Morris.
void parse_eddy_viscosity(const json& e, bool several_materials, RunParameters& d) {
  if (!e.is_object()) fail("'eddy_viscosity' must be an object {\"model\": \"smagorinsky\", \"cs\": 0.12}");
  check_keys(e, "eddy_viscosity", {"model", "cs", "walls"});
  const std::string model = text(need(e, "eddy_viscosity", "model"), "eddy_viscosity.model");
  if (model != "smagorinsky") fail("'eddy_viscosity.model' must be \"smagorinsky\", got \"" + model + "\"");
  const double cs = positive(e, "eddy_viscosity", "cs");
  if (cs > 1.0) fail("'eddy_viscosity.cs' must be at most 1 (Smagorinsky's constant, 0.1-0.2), got " + std::to_string(cs));
  if (!(d.terms & term::morris_viscosity))
    fail("key 'eddy_viscosity' is given but physics term 'morris_viscosity' is not in 'physics' (nu_t adds to its nu)");
  if (several_materials) fail("key 'eddy_viscosity' needs one Newtonian fluid (top-level rho0, viscosity), not 'materials'");
  if (d.viscosity_correction) fail("key 'eddy_viscosity' cannot be combined with 'viscosity_correction'");
  if (d.lees_edwards.on) fail("key 'eddy_viscosity' cannot be combined with 'lees_edwards'");
  if (e.contains("walls")) {
    if (!e["walls"].is_boolean()) fail("'eddy_viscosity.walls' must be true or false, got " + e["walls"].dump());
    d.eddy_walls = e["walls"].get<bool>();
  }
  d.smagorinsky_cs = cs;
}

// `dimension`, `particles_file` and `physics`.
void parse_basics(const json& j, const std::string& deck_dir, RunParameters& d) {
  const auto& dim = need(j, "", "dimension");
  if (!dim.is_number_integer() || (dim.get<int>() != 2 && dim.get<int>() != 3))
    fail("'dimension' must be 2 or 3, got " + dim.dump());
  d.dimension = dim.get<int>();
  d.particles_file = resolve(deck_dir, text(need(j, "", "particles_file"), "particles_file"));
  if (!std::filesystem::exists(d.particles_file))
    fail("particles_file '" + d.particles_file + "' does not exist");
  d.terms = parse_physics(need(j, "", "physics"));
}

// The fluid: `v_max`, then `materials` or the one fluid's top-level EOS keys, and the kernel's `h` and `dx`.
void parse_fluid(const json& j, RunParameters& d) {
  d.v_max = positive(j, "", "v_max");
  if (j.contains("materials")) {
    // Several materials: the fluid keys live in each material, not at the top level.
    for (const char* key : {"rho0", "c0", "gamma", "background_pressure", "viscosity", "min_pressure"})
      if (j.contains(key)) fail("key '" + std::string(key) + "' is given with 'materials'; give it in each material");
    parse_materials(j["materials"], d);
  } else {
    d.rho0 = positive(j, "", "rho0");
    d.c0 = positive(j, "", "c0");
    if (j.contains("gamma")) {
      d.gamma = number(j["gamma"], "gamma");
      if (!(d.gamma >= 1)) fail("'gamma' must be >= 1, got " + std::to_string(d.gamma));
    }
    if (j.contains("background_pressure")) d.background_pressure = number(j["background_pressure"], "background_pressure");
    if (j.contains("min_pressure")) d.min_pressure = min_pressure(j["min_pressure"], "min_pressure", d.background_pressure);
    if (d.c0 < 10.0 * d.v_max)
      fail("c0 = " + std::to_string(d.c0) + " m/s is too small for v_max = " + std::to_string(d.v_max) +
           " m/s; weakly compressible SPH needs c0 >= 10 v_max (density error < 1 %)");
  }
  d.h = positive(j, "", "h");
  d.dx = positive(j, "", "dx");
}

// The viscosities: Morris (`viscosity`, `viscosity_correction`) and artificial (`alpha`, `beta`,
// `artificial_viscosity`).
void parse_viscosities(const json& j, RunParameters& d) {
  if (!j.contains("materials")) {
    require_with_term(j, d, term::morris_viscosity, "viscosity", "morris_viscosity");
    if (j.contains("viscosity")) d.viscosity = positive(j, "", "viscosity");
  }
  if (j.contains("viscosity_correction")) {  // eq. VC1 (viscosity_correction.h)
    if (!j["viscosity_correction"].is_boolean())
      fail("'viscosity_correction' must be true or false, got " + j["viscosity_correction"].dump());
    d.viscosity_correction = j["viscosity_correction"].get<bool>();
    if (d.viscosity_correction && !(d.terms & term::morris_viscosity))
      fail("key 'viscosity_correction' is true but physics term 'morris_viscosity' is not in 'physics'");
  }
  require_with_term(j, d, term::artificial_viscosity, "alpha", "artificial_viscosity");
  if (j.contains("alpha")) d.alpha = non_negative(j, "", "alpha", 0.0);
  if (j.contains("beta") && !(d.terms & term::artificial_viscosity))
    fail("key 'beta' is given but physics term 'artificial_viscosity' is not in 'physics'");
  d.beta = non_negative(j, "", "beta", 0.0);
  if (j.contains("artificial_viscosity")) {
    // {"walls": false}: eqs. 11-12 only between two fluid particles, none against a fixed one.
    if (!(d.terms & term::artificial_viscosity))
      fail("key 'artificial_viscosity' is given but physics term 'artificial_viscosity' is not in 'physics'");
    const auto& av = j["artificial_viscosity"];
    if (!av.is_object()) fail("'artificial_viscosity' must be an object like {\"walls\": false}, got " + av.dump());
    check_keys(av, "artificial_viscosity", {"walls"});
    if (av.contains("walls")) {
      if (!av["walls"].is_boolean())
        fail("'artificial_viscosity.walls' must be true or false, got " + av["walls"].dump());
      d.av_walls = av["walls"].get<bool>();
    }
  }
  if (j.contains("density_diffusion")) d.density_diffusion = non_negative(j, "", "density_diffusion", 0.0);  // eq. DD1
}

// `body_force` and the wall penalty's `meshes` and `wall`.
void parse_forces_and_walls(const json& j, const std::string& deck_dir, RunParameters& d) {
  require_with_term(j, d, term::body_force, "body_force", "body_force");
  if (j.contains("body_force")) d.body_force = vector_of(j["body_force"], "body_force", d.dimension);
  if (j.contains("body_force_solids")) {
    if (!j["body_force_solids"].is_boolean() || !j.contains("body_force"))
      fail("'body_force_solids' must be true or false, beside 'body_force', got " + j["body_force_solids"].dump());
    d.body_force_solids = j["body_force_solids"].get<bool>();
  }

  require_with_term(j, d, term::wall_penalty, "meshes", "wall_penalty");
  require_with_term(j, d, term::wall_penalty, "wall", "wall_penalty");
  if (j.contains("meshes")) parse_meshes(j["meshes"], deck_dir, d);
  if (j.contains("wall")) {
    check_keys(j["wall"], "wall", {"range", "s", "psi"});
    d.wall_range = positive(j["wall"], "wall", "range");
    d.wall_s = positive(j["wall"], "wall", "s");
    d.wall_psi = non_negative(j["wall"], "wall", "psi", 0.0);
    if (!j["wall"].contains("psi")) fail("missing key 'wall.psi'");
    if (!(d.wall_s < d.wall_range)) fail("'wall.s' must be smaller than 'wall.range' (R), got s >= R");
  }
}

// `periodic`: {"axes": [...], "lo": [...], "hi": [...]}, each box at least the kernel support 2h long.
void parse_periodic(const json& p, RunParameters& d) {
  check_keys(p, "periodic", {"axes", "lo", "hi"});
  const auto& axes = need(p, "periodic", "axes");
  if (!axes.is_array() || axes.empty() || axes.size() > static_cast<std::size_t>(d.dimension))
    fail("'periodic.axes' must be a non-empty list of axis indices (0..dimension-1)");
  for (const auto& a : axes) {
    if (!a.is_number_integer() || a.get<int>() < 0 || a.get<int>() >= d.dimension)
      fail("'periodic.axes' entries must be integers in 0.." + std::to_string(d.dimension - 1) + ", got " + a.dump());
    if (std::count(d.periodic_axes.begin(), d.periodic_axes.end(), a.get<int>()))
      fail("'periodic.axes' lists axis " + a.dump() + " twice");
    d.periodic_axes.push_back(a.get<int>());
  }
  d.periodic_lo = vector_of(need(p, "periodic", "lo"), "periodic.lo", axes.size());
  d.periodic_hi = vector_of(need(p, "periodic", "hi"), "periodic.hi", axes.size());
  for (std::size_t i = 0; i < axes.size(); ++i)
    if (!(d.periodic_hi[i] - d.periodic_lo[i] >= 2.0 * d.h))
      fail("periodic box along axis " + std::to_string(d.periodic_axes[i]) +
           " must be at least the kernel support 2h long (periodic.hi - periodic.lo >= 2h)");
}

// The time: `dt` or `time_step`, `t_end`, a resumed run's `t_start` and `step_start`, `max_steps`, `stability`.
void parse_time(const json& j, RunParameters& d) {
  if (j.contains("dt") && j.contains("time_step"))
    fail("give either 'dt' (fixed step) or 'time_step' (adaptive factors), not both");
  if (j.contains("dt")) d.dt = positive(j, "", "dt");
  if (j.contains("time_step")) {
    const auto& t = j["time_step"];
    check_keys(t, "time_step", {"cfl", "viscous", "force"});
    if (t.contains("cfl")) d.cfl = positive(t, "time_step", "cfl");
    if (t.contains("viscous")) d.viscous_factor = positive(t, "time_step", "viscous");
    if (t.contains("force")) d.force_factor = positive(t, "time_step", "force");
  }
  d.t_end = positive(j, "", "t_end");
  if (j.contains("t_start")) {  // a resumed run: its particle file holds the state at t_start
    d.t_start = number(j["t_start"], "t_start");
    if (!(d.t_start >= 0.0 && d.t_start < d.t_end)) fail("'t_start' must be >= 0 s and below 't_end'");
  }
  if (j.contains("step_start")) {
    if (!j["step_start"].is_number_integer() || j["step_start"].get<long>() < 0)
      fail("'step_start' must be an integer >= 0, got " + j["step_start"].dump());
    d.step_start = j["step_start"].get<long>();
  }
  if (j.contains("max_steps")) {
    if (!j["max_steps"].is_number_integer() || j["max_steps"].get<long>() < 1)
      fail("'max_steps' must be a positive integer, got " + j["max_steps"].dump());
    d.max_steps = j["max_steps"].get<long>();
  }
  if (j.contains("stability")) {
    check_keys(j["stability"], "stability", {"max_density_deviation"});
    if (j["stability"].contains("max_density_deviation"))
      d.max_density_deviation = positive(j["stability"], "stability", "max_density_deviation");
  }
}

// `threads`, `neighbour_skin` and `open_boundary_list`.
void parse_run_options(const json& j, RunParameters& d) {
  if (j.contains("threads")) {
    if (!j["threads"].is_number_integer() || j["threads"].get<int>() < 1)
      fail("'threads' must be a positive integer, got " + j["threads"].dump());
    d.threads = j["threads"].get<int>();
  }
  if (j.contains("neighbour_skin")) d.neighbour_skin = positive(j, "", "neighbour_skin");
  if (j.contains("open_boundary_list")) {
    const auto& v = j["open_boundary_list"];
    if (!v.is_string() || (v.get<std::string>() != "kept" && v.get<std::string>() != "rebuilt"))
      fail("'open_boundary_list' must be \"kept\" or \"rebuilt\", got " + v.dump());
    d.open_boundary_list = v.get<std::string>();
  }
}

}  // namespace

RunParameters parse_deck(const json& j, const std::string& deck_dir) {
  check_keys(j, "", {"dimension", "particles_file", "physics", "rho0", "c0", "gamma", "background_pressure", "v_max",
                     "viscosity", "alpha", "beta", "artificial_viscosity", "h", "dx", "body_force", "body_force_solids", "meshes", "wall", "periodic", "inlets",
                     "outlets", "dt", "time_step", "t_end", "t_start", "step_start", "max_steps", "stability", "output", "threads",
                     "materials", "lees_edwards", "neighbour_skin", "viscosity_correction", "eddy_viscosity", "open_boundary_list",
                     "min_pressure", "impactors", "grains", "grain_contact", "density_diffusion"});
  RunParameters d;
  parse_basics(j, deck_dir, d);
  parse_fluid(j, d);
  parse_viscosities(j, d);
  parse_forces_and_walls(j, deck_dir, d);
  if (j.contains("periodic")) parse_periodic(j["periodic"], d);
  if (j.contains("lees_edwards")) parse_lees_edwards(j["lees_edwards"], d);
  if (j.contains("eddy_viscosity")) parse_eddy_viscosity(j["eddy_viscosity"], j.contains("materials"), d);
  parse_open_boundaries(j, d);
  if (j.contains("impactors")) parse_impactors(j["impactors"], d);
  parse_time(j, d);
  if (j.contains("grains")) parse_grains(j["grains"], d);
  if (j.contains("grain_contact")) parse_grain_contact(j["grain_contact"], d);
  parse_output(need(j, "", "output"), deck_dir, d);
  parse_run_options(j, d);
  if (d.density_diffusion > 0.0 && (d.materials.size() > 1 || (d.materials.size() == 1 && d.materials[0].model != "newtonian")))
    fail("'density_diffusion' (eq. DD1) acts in runs of one Newtonian fluid only");
  return d;
}

RunParameters load_deck(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail("cannot open deck '" + path + "'");
  json j;
  try {
    in >> j;
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    fail("deck '" + path + "' is not valid JSON: " + msg);
  }
  return parse_deck(j, std::filesystem::absolute(path).parent_path().string());
}

}  // namespace sph
