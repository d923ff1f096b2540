"""`orchestrator calibrate restitution`: e_n from a sphere drop's first three
impacts, tested by round trips (simulate with a known e_n, fit it back)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from orchestrator.kinds.impact.calibration import drop_model, fit_restitution, observations_from_csv
from orchestrator.case import load_case
from orchestrator.run import run_case
from paths import VERIFICATION

DROP = VERIFICATION / "uhlmann2015_sphere_drop.toml"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "orchestrator", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


@pytest.mark.parametrize("restitution", [0.45, 0.85])
def test_round_trip_through_a_simulated_drop(tmp_path, restitution):
    # a drop simulated by the reference DEM with a known e_n; the fit uses its three contact peaks
    v1 = (2 * 9.81 * 0.010) ** 0.5
    third = v1 / 9.81 + 2 * restitution * v1 / 9.81 * (1 + restitution)  # s, the third impact
    loaded = load_case(DROP, overrides=[f"contacts.0.restitution={restitution}", "expected=[]",
                                        f"simulation.duration={third + 0.005}"])
    run_case(loaded, engine="reference", out_dir=tmp_path / "drop", progress=False)
    proc = cli("calibrate", "restitution", "--run", tmp_path / "drop", "--json")
    assert proc.returncode == 0, proc.stderr
    fit = json.loads(proc.stdout)
    assert fit["restitution"] == pytest.approx(restitution, rel=1e-2)  # measured within 0.1 %
    assert set(fit["residuals"]) == {"F2/F1", "F3/F1", "t2-t1", "t3-t1"}


def write_trace(path: Path, restitution: float, noise: float = 0.0, seed: int = 1) -> None:
    """A force-sensor-like trace of the modelled drop: half-sine pulses at the modelled peaks, sampled every
    0.5 us around the impacts and every 0.1 ms between them, with relative noise."""
    model = drop_model(load_case(DROP).model, restitution)
    rng = np.random.default_rng(seed)
    times = [np.arange(0.0, 0.2, 1e-4)]
    for t_peak in model.peak_times:
        times.append(t_peak + np.arange(-3e-5, 3e-5, 5e-7))
    time = np.unique(np.concatenate(times))
    force = np.zeros_like(time)
    for f_peak, t_peak in zip(model.peak_forces, model.peak_times):
        width = 2.2e-5
        phase = (time - t_peak) / width + 0.5
        pulse = np.where((phase > 0) & (phase < 1), np.sin(np.pi * phase), 0.0)
        force += f_peak * pulse
    force *= 1.0 + noise * rng.standard_normal(len(force))
    # a sensor's offset and a 5 % softer sensor: ratios and time differences do not see either
    time, force = time + 0.3, 0.95 * force
    lines = ["time_s,force_N"] + [f"{t:.9f},{f:.6f}" for t, f in zip(time, force)]
    path.write_text("\n".join(lines) + "\n")


def test_round_trip_through_a_sensor_trace(tmp_path):
    write_trace(tmp_path / "trace.csv", 0.62, noise=0.002)
    observed = observations_from_csv(tmp_path / "trace.csv")
    assert observed.peak_times[0] == pytest.approx(0.3 + drop_model(load_case(DROP).model, 0.62).peak_times[0],
                                                   abs=1e-6)
    fit = fit_restitution(load_case(DROP).model, observed, "trace")
    assert fit.restitution == pytest.approx(0.62, rel=2e-3)
    proc = cli("calibrate", "restitution", "--csv", tmp_path / "trace.csv")
    assert proc.returncode == 0 and proc.stdout.startswith("fitted e_n    ")
    assert float(proc.stdout.split()[2]) == pytest.approx(0.62, rel=2e-3)  # measured 0.6192 with 0.2 % noise
    for words in ("F2/F1 [-]", "t3-t1 [s]", "peaks [N]"):
        assert words in proc.stdout


def test_bad_traces_give_one_clear_error(tmp_path):
    (tmp_path / "short.csv").write_text("time_s,force_N\n0,0\n1,1\n")
    (tmp_path / "text.csv").write_text("time_s,force_N\n" + "a,b\n" * 20)
    one = ["time_s,force_N"] + [f"{k * 1e-3},{10.0 if k == 50 else 0.0}" for k in range(100)]
    (tmp_path / "one.csv").write_text("\n".join(one))
    for name, words in (("missing.csv", "no CSV file"), ("short.csv", "fewer than 10 samples"),
                        ("text.csv", "rows 'time_s,force_N' of numbers"), ("one.csv", "found 1 impact")):
        proc = cli("calibrate", "restitution", "--csv", tmp_path / name)
        assert proc.returncode == 6 and proc.stderr.startswith("error:") and words in proc.stderr, proc.stderr
        assert "Traceback" not in proc.stderr


def test_data_that_contradict_the_model_fail_the_fit(tmp_path, capsys):
    """Peaks that grow: the fit prints its table, then one error line, and exits 1 (not e_n = 0.999, exit 0)."""
    from orchestrator.cli import main

    write_trace(tmp_path / "trace.csv", 0.62)
    lines = (tmp_path / "trace.csv").read_text().splitlines()
    peaks = drop_model(load_case(DROP).model, 0.62).peak_times
    grown = [lines[0]]
    for line in lines[1:]:
        t, f = map(float, line.split(","))
        grown.append(f"{t},{f * (1 if t < 0.3 + peaks[1] - 0.01 else 3 if t < 0.3 + peaks[2] - 0.01 else 9)}")
    (tmp_path / "grown.csv").write_text("\n".join(grown) + "\n")
    assert main(["calibrate", "restitution", "--csv", str(tmp_path / "grown.csv")]) == 1
    out, err = capsys.readouterr()
    assert out.startswith("fitted e_n") and "FAILED FIT" in out
    assert err.count("error:") == 1 and "the fit failed" in err and "peaks grow" in err and "Traceback" not in err
    fit = fit_restitution(load_case(DROP).model, observations_from_csv(tmp_path / "grown.csv"))
    assert fit.failure and max(abs(r) for r in fit.residuals.values()) > 0.1
    assert not fit_restitution(load_case(DROP).model, observations_from_csv(tmp_path / "trace.csv")).failure


def test_an_sph_case_is_not_a_drop(tmp_path, capsys):
    from orchestrator.cli import main

    write_trace(tmp_path / "trace.csv", 0.62)
    tank = DROP.parent / "sph_hydrostatic_tank.toml"
    assert main(["calibrate", "restitution", "--csv", str(tmp_path / "trace.csv"), "--case", str(tank)]) == 2
    err = capsys.readouterr().err
    assert "sph_flow case, not a sphere drop" in err and "Traceback" not in err


def test_a_case_that_is_not_a_drop_is_refused(tmp_path):
    write_trace(tmp_path / "trace.csv", 0.62)
    case = VERIFICATION / "chung_ooi_test1_sphere_sphere.toml"
    proc = cli("calibrate", "restitution", "--csv", tmp_path / "trace.csv", "--case", case)
    assert proc.returncode == 2 and "is not a sphere drop" in proc.stderr and "Traceback" not in proc.stderr
