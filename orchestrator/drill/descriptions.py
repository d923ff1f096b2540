"""What each key of a drill case's [drill] table means, with its unit and source: the fields of
reference.drill_network.DrillNetwork and drill/geometry.DrillGeometry, whose comments these follow. drill/case.py
gives them to the [drill] model's fields, so the docs' key tables and error messages show them; a field without an
entry here fails at import.
"""

from __future__ import annotations

#: [drill] key -> "meaning, unit (source)"; "reconstruction" marks a value the paper does not state.
DRILL_DESCRIPTIONS = {
    # fluid
    "rho": "coolant density, kg/m^3 (a water-based emulsion; not stated in the paper)",
    "mu": "coolant dynamic viscosity, Pa s (water at 20 C; a 5 % emulsion is 1-1.5 mPa s)",
    "p_ambient": "absolute pressure of the flooded work area, Pa (paper, sect. 4)",
    "p_vapour": "absolute vapour pressure of the coolant, Pa (water at 20 C; below it the liquid cavitates)",
    # bore and tubes
    "d_bore": "drilling diameter d, m (paper: 30 mm)",
    "d_outer_tube_od": "outer tube's outside diameter, m (reconstruction: about 0.8 d, a 3 mm radial clearance to "
                       "the bore)",
    "d_outer_tube_id": "outer tube's inside diameter, m (reconstruction: a 2 mm wall for the 8-10 kN feed force)",
    "d_diff": "difference in diameter of the annular gap d_Diff, m (paper: 1 mm, diametral: a 0.5 mm radial gap)",
    "d_inner_tube_id": "inner tube's inside diameter, m (reconstruction: a 1.5 mm wall on its outside diameter "
                       "d_outer_tube_id - d_diff)",
    "tube_length": "length of the tubes from the feed to the drill head, m (reconstruction: the bore depth l/D = 10 "
                   "with chuck, connector and head shank)",
    "roughness": "tubes' wall roughness, m (drawn steel tube, Moody)",
    # ejector nozzles
    "n_ejector_nozzles": "ejector nozzles in the ring at the inner tube's feed end, - (reconstruction, Fig. 1C)",
    "d_ejector_nozzle": "ejector nozzle diameter, m (reconstruction: about a third of V_total through the nozzles, "
                        "35 % at 60 l/min)",
    "k_primary": "loss coefficient K_p of the jet pump's primary nozzle, - (a short drilled nozzle; Karassik: "
                 "0.05-0.15)",
    "k_secondary": "loss coefficient K_s of the jet pump's secondary entry, - (Karassik)",
    "mixing_length": "inner tube behind the nozzles that acts as the mixing throat, m (about 7.5 inner diameters; "
                     "Karassik: 6-8)",
    "discharge_length": "rest of the inner tube from the mixing throat's end to the chip outlet, m",
    # drill head
    "n_holes": "adduction holes from the annular gap out through the head, - (reconstruction)",
    "d_hole": "adduction hole diameter, m (reconstruction, Fig. 2)",
    "cd_hole": "discharge coefficient of an adduction hole, - (a short hole fed by a cross-flow; Lichtarowicz et al. "
               "1965: 0.6-0.8)",
    "front_area": "free passage from the holes' exits to the cutting edges, m^2 (the flats and chip space on the "
                  "head's periphery; reconstruction)",
    "k_cutting_zone": "loss coefficient of the turns round the cutting edges into the chip mouth, on front_area, - "
                      "(Idelchik: about two 90-degree turns; reconstruction)",
    "d_chip_mouth": "equivalent diameter of the chip mouth, m (reconstruction; below d_inner_tube_id)",
    "k_chip_mouth_entry": "loss coefficient of the sharp entrance into the chip mouth, - (Rennels)",
    # leak path back to the bore mouth
    "d_head_body": "head body's diameter behind the guide pads, m (reconstruction; the pads at the bore's diameter)",
    "head_rear_length": "head length from the holes' exits to the tube joint, m (reconstruction)",
    "pad_blockage": "share of the head clearance's circumference the guide pads take, - (reconstruction)",
    "bore_depth": "current drilled depth: the length of the tube/bore clearance, m (l/D = 10)",
    "sensor_b_from_feed": "sensor B's distance into the annular gap from the feed, m (Fig. 5B; reconstruction)",
    # geometry
    "groove_length": "length of the groove at the head's rear that carries the annular gap to the holes, m "
                     "(reconstruction: twice the hole diameter)",
    "groove_depth": "the groove's radial depth beyond the gap's outer radius, a collector chamber round the holes' "
                    "entrances, m (0: the gap's own width)",
    "front_clearance": "chip space ahead of the head's face as one uniform gap to the bore bottom, m "
                       "(reconstruction: 2 mm gives the chip mouth's edge the network's front_area)",
    "nozzle_angle_deg": "the ejector nozzles' tilt rearward from the tube's cross-section, deg (reconstruction, "
                        "Fig. 1C)",
    "workpiece_wall": "workpiece's wall round the bore and its floor ahead of the bore bottom, m (room for boundary "
                      "particles)",
    "sections": "sides of the revolved polygons, - (96: a 0.07 % volume deficit)",
}
