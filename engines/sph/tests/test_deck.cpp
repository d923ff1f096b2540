// Deck validation: each bad input is rejected with a message naming the problem.
#include <nlohmann/json.hpp>

#include "check.h"
#include "deck.h"
#include "physics_terms.h"
#include "setup.h"
#include "test_files.h"

using namespace sph;
using nlohmann::json;

namespace {

std::filesystem::path deck_dir() {
  static const auto dir = [] {
    const auto d = testfiles::scratch("deck");
    testfiles::ParticleRows p;
    p.add({0.0, 0.0}, {0.0, 0.0}, 1e-3, 1000.0, 0);
    p.write(d / "particles.h5");
    return d;
  }();
  return dir;
}

json good_deck() {
  return json::parse(R"({
    "dimension": 2, "particles_file": "particles.h5",
    "physics": ["morris_viscosity", "body_force"],
    "rho0": 1000, "c0": 20, "v_max": 1.0, "viscosity": 1e-6, "h": 1.3e-3, "dx": 1e-3,
    "body_force": [0, -9.81], "t_end": 0.1,
    "output": {"file": "out.h5", "frame_interval": 0.01}
  })");
}

// The InputError message for a deck, or "" when it is accepted.
std::string rejection(const json& j) {
  try {
    parse_deck(j, deck_dir().string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool mentions(const std::string& msg, const std::string& part) { return msg.find(part) != std::string::npos; }

}  // namespace

TEST(good_deck_is_accepted) {
  const RunParameters d = parse_deck(good_deck(), deck_dir().string());
  CHECK(d.dimension == 2);
  CHECK(d.terms == (term::morris_viscosity | term::body_force));
  CHECK(d.gamma == 7.0);
  CHECK(!d.dt.has_value());
  CHECK(d.series_interval == d.frame_interval);
  CHECK(mentions(d.output_file, "out.h5"));
  CHECK(d.terms_string() == "continuity,tait_eos,pressure_gradient,morris_viscosity,body_force");
  CHECK(d.body_force_solids);  // by default a solid takes the body force too (gravity)
  json j = good_deck();
  j["body_force_solids"] = false;
  CHECK(!parse_deck(j, deck_dir().string()).body_force_solids);
}

TEST(unknown_keys_are_named_with_the_allowed_ones) {
  json j = good_deck();
  j["smoothing"] = 1.0;
  std::string msg = rejection(j);
  CHECK(mentions(msg, "unknown key 'smoothing'") && mentions(msg, "allowed keys:") && mentions(msg, "particles_file"));
  j = good_deck();
  j["output"]["every"] = 3;
  msg = rejection(j);
  CHECK(mentions(msg, "unknown key 'output.every'") && mentions(msg, "frame_interval"));
  j = good_deck();
  j["physics"].push_back("turbulence");
  CHECK(mentions(rejection(j), "unknown physics term 'turbulence'"));
}

TEST(bad_values_are_rejected) {
  json j = good_deck();
  j["h"] = 0.0;
  CHECK(mentions(rejection(j), "'h' must be > 0"));
  j = good_deck();
  j["dx"] = -1e-3;
  CHECK(mentions(rejection(j), "'dx' must be > 0"));
  j = good_deck();
  j["c0"] = 9.0;  // < 10 v_max
  CHECK(mentions(rejection(j), "c0 >= 10 v_max"));
  j = good_deck();
  j["particles_file"] = "nowhere.h5";
  CHECK(mentions(rejection(j), "does not exist"));
  j = good_deck();
  j["dimension"] = 4;
  CHECK(mentions(rejection(j), "'dimension' must be 2 or 3"));
  j = good_deck();
  j["body_force"] = {0, 0, -9.81};
  CHECK(mentions(rejection(j), "'body_force' must be a list of 2 numbers"));
  j = good_deck();
  j["body_force_solids"] = "no";
  CHECK(mentions(rejection(j), "'body_force_solids' must be true or false, beside 'body_force'"));
  j = good_deck();
  j["h"] = "small";
  CHECK(mentions(rejection(j), "'h' must be a number"));
  j = good_deck();
  j["dt"] = 1e-5;
  j["time_step"] = {{"cfl", 0.2}};
  CHECK(mentions(rejection(j), "either 'dt'"));
  j = good_deck();
  j.erase("t_end");
  CHECK(mentions(rejection(j), "missing key 't_end'"));
}

TEST(neighbour_skin_defaults_to_a_tenth_of_the_support) {
  CHECK(parse_deck(good_deck(), deck_dir().string()).neighbour_skin == 0.1);
  json j = good_deck();
  j["neighbour_skin"] = 0.25;
  CHECK(parse_deck(j, deck_dir().string()).neighbour_skin == 0.25);
  j["neighbour_skin"] = 0.0;
  CHECK(mentions(rejection(j), "'neighbour_skin' must be > 0"));
}

TEST(term_keys_must_match_the_physics_list) {
  json j = good_deck();
  j["alpha"] = 0.1;
  CHECK(mentions(rejection(j), "'alpha' is given but physics term 'artificial_viscosity'"));
  j = good_deck();
  j["artificial_viscosity"] = json::parse(R"({"walls": false})");
  CHECK(mentions(rejection(j), "'artificial_viscosity' is given but physics term 'artificial_viscosity'"));
  j["physics"].push_back("artificial_viscosity");
  j["alpha"] = 0.1;
  CHECK(!parse_deck(j, deck_dir().string()).av_walls);
  j["artificial_viscosity"]["walls"] = 1;
  CHECK(mentions(rejection(j), "'artificial_viscosity.walls' must be true or false"));
  j["artificial_viscosity"] = json::parse(R"({"wall": false})");
  CHECK(mentions(rejection(j), "artificial_viscosity"));
  j.erase("artificial_viscosity");
  CHECK(parse_deck(j, deck_dir().string()).av_walls);  // default: today's behaviour
  j = good_deck();
  CHECK(!parse_deck(j, deck_dir().string()).viscosity_correction);  // default: the plain Morris sum
  j["viscosity_correction"] = true;
  CHECK(parse_deck(j, deck_dir().string()).viscosity_correction);
  CHECK(mentions(parse_deck(j, deck_dir().string()).terms_string(), "with viscosity_correction"));
  j["viscosity_correction"] = "yes";
  CHECK(mentions(rejection(j), "'viscosity_correction' must be true or false"));
  j["viscosity_correction"] = true;
  j["physics"] = json::array({"body_force"});
  j.erase("viscosity");
  CHECK(mentions(rejection(j), "'viscosity_correction' is true but physics term 'morris_viscosity' is not in"));
  j = good_deck();  // Smagorinsky's eddy viscosity (eddy_viscosity.h)
  CHECK(parse_deck(j, deck_dir().string()).smagorinsky_cs == 0.0);
  j["eddy_viscosity"] = json::parse(R"({"model": "smagorinsky", "cs": 0.12})");
  CHECK(parse_deck(j, deck_dir().string()).smagorinsky_cs == 0.12);
  CHECK(mentions(parse_deck(j, deck_dir().string()).terms_string(), "with eddy_viscosity"));
  CHECK(parse_deck(j, deck_dir().string()).eddy_walls);
  j["eddy_viscosity"]["walls"] = false;
  CHECK(!parse_deck(j, deck_dir().string()).eddy_walls);
  j["eddy_viscosity"]["walls"] = "no";
  CHECK(mentions(rejection(j), "'eddy_viscosity.walls' must be true or false"));
  j["eddy_viscosity"].erase("walls");
  j["eddy_viscosity"]["cs"] = 1.5;
  CHECK(mentions(rejection(j), "'eddy_viscosity.cs' must be at most 1"));
  j["eddy_viscosity"]["cs"] = -0.1;
  CHECK(mentions(rejection(j), "eddy_viscosity.cs"));
  j["eddy_viscosity"] = json::parse(R"({"model": "wale", "cs": 0.12})");
  CHECK(mentions(rejection(j), "'eddy_viscosity.model' must be \"smagorinsky\", got \"wale\""));
  j["eddy_viscosity"] = json::parse(R"({"model": "smagorinsky", "cs": 0.12, "length": 1})");
  CHECK(mentions(rejection(j), "length"));
  j["eddy_viscosity"] = 0.12;
  CHECK(mentions(rejection(j), "'eddy_viscosity' must be an object"));
  j["eddy_viscosity"] = json::parse(R"({"model": "smagorinsky", "cs": 0.12})");
  j["viscosity_correction"] = true;
  CHECK(mentions(rejection(j), "cannot be combined with 'viscosity_correction'"));
  j.erase("viscosity_correction");
  j["physics"] = json::array({"body_force"});
  j.erase("viscosity");
  CHECK(mentions(rejection(j), "'eddy_viscosity' is given but physics term 'morris_viscosity' is not in 'physics'"));
  j = good_deck();
  j.erase("viscosity");
  CHECK(mentions(rejection(j), "'morris_viscosity' is on but key 'viscosity' is missing"));
  j = good_deck();
  j["physics"].push_back("wall_penalty");
  CHECK(mentions(rejection(j), "key 'meshes' is missing"));
  j["meshes"] = json::parse(R"([{"name": "floor", "vertices": [[0, 0], [1, 0]], "faces": [[0, 1]]}])");
  j["wall"] = json::parse(R"({"range": 1e-3, "s": 2e-3, "psi": 1.0})");
  CHECK(mentions(rejection(j), "'wall.s' must be smaller"));
  j["wall"]["s"] = 0.5e-3;
  CHECK(rejection(j).empty());
  j["meshes"][0]["file"] = "missing.h5";
  CHECK(mentions(rejection(j), "both 'file' and inline"));
}

TEST(periodic_and_output_sections) {
  json j = good_deck();
  j["periodic"] = json::parse(R"({"axes": [0], "lo": [0.0], "hi": [1e-3]})");
  CHECK(mentions(rejection(j), "at least the kernel support"));
  j["periodic"]["hi"] = {1e-2};
  CHECK(rejection(j).empty());
  j["periodic"]["axes"] = {2};
  CHECK(mentions(rejection(j), "'periodic.axes' entries must be integers in 0..1"));
  j = good_deck();
  j["output"]["flow_planes"] = json::parse(R"([{"name": "q", "center": [0, 0], "normal": [1, 0]}])");
  CHECK(mentions(rejection(j), "exactly one of 'radius'"));
  j["output"]["flow_planes"][0]["radius"] = 1e-3;
  j["output"]["probes"] = json::parse(R"([{"name": "p", "point": [0, 0]}, {"name": "p", "point": [1, 0]}])");
  CHECK(mentions(rejection(j), "duplicate name 'p'"));
}

TEST(inlets_and_outlets) {
  json j = good_deck();
  j["inlets"] = json::parse(R"([{"name": "feed", "center": [0, 0], "normal": [1, 0], "radius": 0.01, "velocity": 0.5}])");
  j["outlets"] = json::parse(R"([{"name": "drain", "center": [0.1, 0], "normal": [1, 0], "radius": 0.01}])");
  const RunParameters d = parse_deck(j, deck_dir().string());
  CHECK(d.inlets.size() == 1 && d.outlets.size() == 1 && d.inlets[0].layers == 3 && d.inlets[0].velocity == 0.5);
  j["inlets"][0]["velocity"] = 2.0;  // above v_max
  CHECK(mentions(rejection(j), "exceeds v_max"));
  j["inlets"][0]["velocity"] = 0.5;
  j["inlets"][0]["layers"] = 2;  // 2 dx < 2h
  CHECK(mentions(rejection(j), "must cover the kernel support"));
  j["inlets"][0].erase("layers");
  j["outlets"][0]["speed"] = 1.0;
  CHECK(mentions(rejection(j), "unknown key 'outlets[0].speed'"));
  j["outlets"][0].erase("speed");
  j["outlets"][0]["name"] = "feed";
  CHECK(mentions(rejection(j), "duplicate name 'feed'"));
}

// Materials: a deck without `materials` is one Newtonian material of the
// top-level keys; with it, each material carries its own EOS keys and model keys.
TEST(min_pressure_lies_below_the_rest_pressure) {
  json j = good_deck();
  j["min_pressure"] = -0.99e5;
  const RunParameters d = parse_deck(j, deck_dir().string());
  CHECK(d.material_list()[0].min_pressure.value_or(0.0) == -0.99e5);
  j["min_pressure"] = 0.0;  // background_pressure 0: a floor at the rest pressure holds no tension at all
  CHECK(mentions(rejection(j), "'min_pressure' = 0.000000 Pa must lie below the rest pressure"));
  j["min_pressure"] = "low";
  CHECK(mentions(rejection(j), "'min_pressure' must be a number"));
}

TEST(deck_without_materials_is_one_newtonian_material) {
  const RunParameters d = parse_deck(good_deck(), deck_dir().string());
  CHECK(d.materials.empty());
  const auto list = d.material_list();
  CHECK(list.size() == 1);
  CHECK(list[0].model == "newtonian");
  CHECK(list[0].rho0 == 1000.0 && list[0].c0 == 20.0 && list[0].gamma == 7.0 && list[0].viscosity == 1e-6);
}

TEST(materials_list_is_parsed_and_checked) {
  json j = good_deck();
  for (const char* key : {"rho0", "c0", "viscosity"}) j.erase(key);
  j["materials"] = json::parse(R"([
    {"name": "water", "model": "newtonian", "rho0": 1000, "c0": 20, "viscosity": 1e-6},
    {"name": "oil", "model": "newtonian", "rho0": 800, "c0": 25, "gamma": 1, "background_pressure": 10, "viscosity": 1e-4}])");
  const RunParameters d = parse_deck(j, deck_dir().string());
  CHECK(d.materials.size() == 2);
  CHECK(d.materials[1].name == "oil" && d.materials[1].rho0 == 800.0 && d.materials[1].gamma == 1.0);
  CHECK(d.materials[1].background_pressure == 10.0 && d.materials[1].viscosity == 1e-4);
  CHECK(d.rho0 == 1000.0 && d.c0 == 20.0);  // the top-level values mirror materials[0]

  json top = j;
  top["rho0"] = 1000;
  CHECK(mentions(rejection(top), "'rho0' is given with 'materials'"));
  json model = j;
  model["materials"][1]["model"] = "bingham";
  CHECK(mentions(rejection(model), "not a material model; known: newtonian"));
  json missing = j;
  missing["materials"][0].erase("viscosity");
  CHECK(mentions(rejection(missing), "materials[0].viscosity"));
  json unknown = j;
  unknown["materials"][0]["shear_modulus"] = 1.0;
  CHECK(mentions(rejection(unknown), "unknown key 'materials[0].shear_modulus'"));
  json slow = j;
  slow["materials"][1]["c0"] = 5.0;
  CHECK(mentions(rejection(slow), "c0 >= 10 v_max"));
  json twice = j;
  twice["materials"][1]["name"] = "water";
  CHECK(mentions(rejection(twice), "duplicate name 'water'"));
}

// A PTT material (materials/ptt.h) and its keys; the `eos` choice; Lees-Edwards boundaries.
TEST(ptt_material_and_lees_edwards_are_parsed_and_checked) {
  json j = good_deck();
  j.erase("rho0"), j.erase("c0"), j.erase("viscosity");
  j["physics"] = json::array();
  j.erase("body_force");
  j["materials"] = json::parse(R"([{"name": "melt", "model": "ptt", "rho0": 1000, "c0": 20, "eos": "quadratic",
      "epsilon": 0.1, "solvent_viscosity": 0.5, "modes": [{"lambda": 0.1, "eta": 100}, {"lambda": 0.01, "eta": 10}]}])");
  j["periodic"] = json::parse(R"({"axes": [0, 1], "lo": [0, 0], "hi": [0.01, 0.01]})");
  j["lees_edwards"] = json::parse(R"({"shear_rate": 10})");
  const RunParameters d = parse_deck(j, deck_dir().string());
  CHECK(d.materials[0].model == "ptt" && d.materials[0].quadratic_eos);
  CHECK(d.materials[0].mode_lambda.size() == 2 && d.materials[0].mode_eta[1] == 10.0);
  CHECK(d.materials[0].epsilon == 0.1 && d.materials[0].solvent_viscosity == 0.5);
  CHECK(d.lees_edwards.on && d.lees_edwards.shear_rate == 10.0);
  json bad_eos = j;
  bad_eos["materials"][0]["eos"] = "ideal_gas";
  CHECK(mentions(rejection(bad_eos), "'materials[0].eos' = 'ideal_gas'"));
  json no_modes = j;
  no_modes["materials"][0].erase("modes");
  CHECK(mentions(rejection(no_modes), "materials[0].modes"));
  json bad_mode = j;
  bad_mode["materials"][0]["modes"][1]["lambda"] = -1.0;
  CHECK(mentions(rejection(bad_mode), "'materials[0].modes[1].lambda' must be > 0"));
  json extra = j;
  extra["materials"][0]["modes"][0]["G"] = 1.0;
  CHECK(mentions(rejection(extra), "materials[0].modes[0].G"));
  json many = j;
  for (int k = 0; k < 8; ++k) many["materials"][0]["modes"].push_back({{"lambda", 1.0}, {"eta", 1.0}});
  CHECK(mentions(rejection(many), "'materials[0].modes' must be a list of 1 to 8"));
  json negative = j;
  negative["materials"][0]["epsilon"] = -0.1;
  CHECK(mentions(rejection(negative), "'materials[0].epsilon' must be >= 0"));
  json oscillatory = j;
  oscillatory["lees_edwards"] = json::parse(R"({"amplitude": 0.5, "omega": 6.28})");
  CHECK(parse_deck(oscillatory, deck_dir().string()).lees_edwards.omega == 6.28);
  json both = j;
  both["lees_edwards"]["amplitude"] = 0.5;
  CHECK(mentions(rejection(both), "'lees_edwards' takes either 'shear_rate'"));
  json no_omega = j;
  no_omega["lees_edwards"] = json::parse(R"({"amplitude": 0.5})");
  CHECK(mentions(rejection(no_omega), "lees_edwards.omega"));
  json not_periodic = j;
  not_periodic["periodic"] = json::parse(R"({"axes": [0], "lo": [0], "hi": [0.01]})");
  CHECK(mentions(rejection(not_periodic), "'periodic.axes' must list axes 0 and 1"));
}

TEST(a_resumed_runs_start_is_checked) {
  json j = good_deck();
  j["t_start"] = 0.04;
  j["step_start"] = 1200;
  const RunParameters d = parse_deck(j, deck_dir().string());
  CHECK(d.t_start == 0.04 && d.step_start == 1200);
  CHECK(parse_deck(good_deck(), deck_dir().string()).t_start == 0.0);
  j["t_start"] = 0.1;  // = t_end: nothing left to run
  CHECK(mentions(rejection(j), "'t_start' must be >= 0 s and below 't_end'"));
  j["t_start"] = -1e-3;
  CHECK(mentions(rejection(j), "'t_start' must be >= 0 s and below 't_end'"));
  j = good_deck();
  j["step_start"] = -3;
  CHECK(mentions(rejection(j), "'step_start' must be an integer >= 0"));
}

// A new run's fluid starts within v_max (its c0 was chosen for that speed); a resumed run's frame may hold a jet
// faster than v_max, which its run reached and ran on with, so only c0 bounds it there.
TEST(a_resumed_runs_fluid_may_exceed_v_max_but_not_c0) {
  ParticleInput in;
  in.n = 2, in.dimension = 2;
  in.positions = {0.0, 0.0, 1e-3, 0.0};
  in.velocities = {1.5, 0.0, 0.0, 0.0};  // m/s: above v_max = 1, below c0 = 20
  in.masses = {1e-3, 1e-3}, in.densities = {1000.0, 1000.0}, in.kind = {0, 0};
  auto message = [&](const RunParameters& d) {
    try {
      make_particles<2>(d, in);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  json j = good_deck();
  CHECK(mentions(message(parse_deck(j, deck_dir().string())), "starts at 1.500000"));
  CHECK(mentions(message(parse_deck(j, deck_dir().string())), "above v_max = 1.000000"));
  j["t_start"] = 0.04, j["step_start"] = 1200;
  CHECK(message(parse_deck(j, deck_dir().string())).empty());
  in.velocities[0] = 25.0;  // above c0 = 20
  CHECK(mentions(message(parse_deck(j, deck_dir().string())), "above its material's c0 = 20.000000"));
}
