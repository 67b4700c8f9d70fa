#!/usr/bin/env python3
"""Writes the systematic manifests of the bad-input corpus (README.md):
study_toml_values.cases (every numeric key of base/study.toml given values of
the wrong kind or out of range) and set_overrides.cases (the same through
--set). Deterministic: run it again after changing base/study.toml or a
message, and review the diff. The other manifests are written by hand."""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
STUDY = open(os.path.join(HERE, "base", "study.toml")).read().splitlines()
DRY = "doe study.toml --dry-run --output out"


def line_of(prefix, start=0):
    for i, l in enumerate(STUDY[start:], start + 1):
        if l.startswith(prefix):
            return i, l
    raise SystemExit("not in base/study.toml: " + prefix)


# key in the file, its table's first line (to find the right occurrence), dotted path, expected-text, kind
POS = "a number > 0"
DENSE = "30000 (no material is denser; osmium: 22 590 kg/m3)"
STIFF = "1e+13 (no material is stiffer; diamond: 1.2e12 Pa)"
ROUGH = "10 (a friction coefficient above 10 is a slip)"
LARGE = "100 (no laboratory test is larger)"
# key, its table's header, dotted path, its range's text, kind, and the physical bound's text (huge values)
KEYS = [
    ("density_kg_m3", "[material]", "material.density_kg_m3", POS, "positive", DENSE),
    ("shear_modulus_pa", "[material]", "material.shear_modulus_pa", POS, "positive", STIFF),
    ("poisson_ratio", "[material]", "material.poisson_ratio", "a number in (-1, 0.5)", "signed", None),
    ("density_kg_m3", "[wall_material]", "wall_material.density_kg_m3", POS, "positive", DENSE),
    ("youngs_modulus_pa", "[wall_material]", "wall_material.youngs_modulus_pa", POS, "positive", STIFF),
    ("poisson_ratio", "[wall_material]", "wall_material.poisson_ratio", "a number in (-1, 0.5)", "signed", None),
    ("restitution", "[interaction.particle_particle]", "interaction.particle_particle.restitution", "a number in (0, 1]", "bounded", None),
    ("sliding_friction", "[interaction.particle_particle]", "interaction.particle_particle.sliding_friction", "a number >= 0", "atleast", ROUGH),
    ("rolling_friction", "[interaction.particle_particle]", "interaction.particle_particle.rolling_friction", "a number >= 0", "atleast", ROUGH),
    ("restitution", "[interaction.particle_wall]", "interaction.particle_wall.restitution", "a number in (0, 1]", "bounded", None),
    ("sliding_friction", "[interaction.particle_wall]", "interaction.particle_wall.sliding_friction", "a number >= 0", "atleast", ROUGH),
    ("rolling_friction", "[interaction.particle_wall]", "interaction.particle_wall.rolling_friction", "a number >= 0", "atleast", ROUGH),
    ("rest_speed_m_s", "[protocol]", "protocol.rest_speed_m_s", POS, "positive", None),
    ("max_settle_s", "[protocol]", "protocol.max_settle_s", POS, "positive", None),
    ("max_flow_s", "[protocol]", "protocol.max_flow_s", POS, "positive", None),
    ("upper_diameter_m", "[apparatus.sandglass]", "apparatus.sandglass.upper_diameter_m", POS, "positive", LARGE),
    ("upper_height_m", "[apparatus.sandglass]", "apparatus.sandglass.upper_height_m", POS, "positive", LARGE),
    ("hopper_half_angle_deg", "[apparatus.sandglass]", "apparatus.sandglass.hopper_half_angle_deg", "a number in (0, 80)", "bounded", None),
    ("orifice_diameter_m", "[apparatus.sandglass]", "apparatus.sandglass.orifice_diameter_m", POS, "positive", LARGE),
    ("fill_mass_kg", "[apparatus.sandglass]", "apparatus.sandglass.fill_mass_kg", POS, "positive", None),
    ("lower_diameter_m", "[apparatus.sandglass]", "apparatus.sandglass.lower_diameter_m", POS, "positive", LARGE),
    ("drop_height_m", "[apparatus.sandglass]", "apparatus.sandglass.drop_height_m", POS, "positive", LARGE),
    ("slice_thickness_diameters", "[apparatus.sandglass]", "apparatus.sandglass.slice_thickness_diameters", "a number >= 2", "atleast", None),
    ("coarse_graining_factor", "[apparatus.sandglass]", "apparatus.sandglass.coarse_graining_factor", POS, "positive", None),
    ("shear_modulus_pa", "[apparatus.sandglass]", "apparatus.sandglass.shear_modulus_pa", "a number >= 0", "atleast", None),
]

# value as written, how the message shows it, for which kinds
VALUES = [
    ("-1", "got -1", {"bounded", "bounded0", "positive", "atleast"}),
    ("-2.5", "got -2.5", {"signed"}),
    ("0", "got 0", {"bounded", "positive"}),
    ('"abc"', 'got "abc" (a string)', None),
    ("true", "got true (a boolean)", None),
    ("[1, 2]", "(an array)", None),
    ("inf", "got inf", None),
    ("nan", "got nan", None),
    ("1e308", "got 1e+308", "huge"),
    ("0x10", "written in hexadecimal, octal or binary", {"bounded", "bounded0", "positive", "atleast"}),
]


def block(name, edits, run, code, expects):
    out = ["case: " + name]
    out += edits
    out.append("run: " + run)
    out.append("exit: %d" % code)
    out += ["expect: " + e for e in expects]
    return "\n".join(out) + "\n"


def study_toml_values():
    cases = []
    for key, table, path, expected, kind, most in KEYS:
        t_line, _ = line_of(table)
        n, text = line_of(key + " =", t_line)
        # From the table's header to the key, so that a key of two tables is changed in the right one.
        context = "\\n".join(STUDY[t_line - 1:n - 1])
        slug = path.replace(".", "-")
        for value, shown, kinds in VALUES:
            if kinds == "huge":
                if most is None and kind not in ("bounded", "signed"):
                    continue
            elif kinds is not None and kind not in kinds:
                continue
            new = key + " = " + value
            vslug = {"-1": "negative", "-2.5": "below", "0": "zero", '"abc"': "string", "true": "boolean",
                     "[1, 2]": "array", "inf": "inf", "nan": "nan", "1e308": "huge", "0x10": "hex"}[value]
            what = ("at most " + most) if (value == "1e308" and most) else expected
            cases.append(block(slug + "-" + vslug, ["sub: study.toml | %s\\n%s | %s\\n%s" % (context, text, context, new)], DRY, 2,
                               ["study.toml:%d: %s: expected %s" % (n, path, what), shown]))
    return cases


SETS = [
    ("mu_s=1e6", "interaction.particle_particle.sliding_friction", "at most " + ROUGH, "got 1000000"),
    ("mu_s=-0.1", "interaction.particle_particle.sliding_friction", "a number >= 0", "got -0.1"),
    ("mu_r=11", "interaction.particle_particle.rolling_friction", "at most " + ROUGH, "got 11"),
    ("mu_s_wall=1e6", "interaction.particle_wall.sliding_friction", "at most " + ROUGH, "got 1000000"),
    ("mu_r_wall=-1", "interaction.particle_wall.rolling_friction", "a number >= 0", "got -1"),
    ("material.density_kg_m3=1e308", "material.density_kg_m3", "at most " + DENSE, "got 1e+308"),
    ("material.density_kg_m3=-1", "material.density_kg_m3", POS, "got -1"),
    ("material.shear_modulus_pa=1e30", "material.shear_modulus_pa", "at most " + STIFF, "got 1e+30"),
    ("wall_material.youngs_modulus_pa=0", "wall_material.youngs_modulus_pa", POS, "got 0"),
    ("interaction.particle_wall.restitution=1.5", "interaction.particle_wall.restitution", "a number in (0, 1]", "got 1.5"),
    ("interaction.particle_particle.restitution=0", "interaction.particle_particle.restitution", "a number in (0, 1]", "got 0"),
    ("protocol.max_flow_s=-5", "protocol.max_flow_s", "a number > 0", "got -5"),
    ("protocol.check_interval_s=0", "protocol.check_interval_s", "a number > 0", "got 0"),
    ("protocol.sample_interval_s=-1", "protocol.sample_interval_s", "a number > 0", "got -1"),
    ("protocol.stall_time_s=0", "protocol.stall_time_s", "a number > 0", "got 0"),
    ("protocol.time_step_fraction_of_rayleigh=2", "protocol.time_step_fraction_of_rayleigh", "a number in (0, 1]", "got 2"),
    ("apparatus.sandglass.hopper_half_angle_deg=90", "apparatus.sandglass.hopper_half_angle_deg", "a number in (0, 80)", "got 90"),
    ("apparatus.sandglass.orifice_diameter_m=1e6", "apparatus.sandglass.orifice_diameter_m", "at most " + LARGE, "got 1000000"),
    ("apparatus.sandglass.upper_height_m=-0.1", "apparatus.sandglass.upper_height_m", POS, "got -0.1"),
    ("apparatus.sandglass.coarse_graining_factor=0", "apparatus.sandglass.coarse_graining_factor", "a number > 0", "got 0"),
    ("apparatus.sandglass.slice_thickness_diameters=1", "apparatus.sandglass.slice_thickness_diameters", "a number >= 2", "got 1"),
    ("apparatus.sandglass.fill_lattice_spacing_diameters=5", "apparatus.sandglass.fill_lattice_spacing_diameters", "a number in (1, 3]", "got 5"),
    ("study.threads=0", "study.threads", "an integer >= 1 and <= 4096", "got 0"),
    ("study.seed=-3", "study.seed", "an integer >= 0", "got -3"),
]


def set_overrides():
    cases = []
    for assignment, path, expected, shown in SETS:
        slug = "set-" + assignment.split("=")[0].replace(".", "-") + "-" + \
            assignment.split("=")[1].replace(".", "p").replace("-", "minus").replace("+", "")
        cases.append(block(slug, [], DRY + " --set " + assignment, 2,
                           ["study.toml:", path + ": expected " + expected, shown, "(from --set " + assignment + ")"]))
    return cases


def write(name, header, cases):
    with open(os.path.join(HERE, name), "w") as f:
        f.write(header + "\n")
        f.write("\n".join(cases))


write("study_toml_values.cases",
      "# Generated by generate_cases.py from base/study.toml: every numeric key given a value of\n"
      "# the wrong kind or outside its range; each is refused at its line with its range.",
      study_toml_values())
write("set_overrides.cases",
      "# Generated by generate_cases.py: bad values through --set (and its aliases); each is\n"
      "# refused naming the key, the range and the --set it came from.",
      set_overrides())
