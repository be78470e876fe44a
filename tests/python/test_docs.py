"""The docs name what the program writes: every top-level key of summary.json that a range of
runs writes is named in docs/summary.md."""
import os
import re

import gfmd

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def documented_keys():
    text = open(os.path.join(ROOT, "docs", "summary.md")).read()
    return set(re.findall(r"`([a-z_0-9<>]+)`", text))


def test_summary_keys_are_documented():
    top = gfmd.Topography.hertz(64, 2.0, radius=1.0)
    summaries = [
        gfmd.run_toml("[grid]\nnx = 64\nlx = 2.0\n[elastic]\npoisson = 0.3\n[indenter]\ntype = \"hertz\"\n"
                      "radius = 1.0\n[load]\nforce = 0.005\n[friction]\ncoefficient = 0.3\n[stress]\n"
                      "depths = [0.05]\npost_analysis = true\n")["summary"],
        gfmd.solve(top, gfmd.ElasticBody(poisson=0.3), force=0.005, friction=0.3, creepage=0.5).summary,
        gfmd.solve(top, gfmd.ElasticBody(poisson=0.5), approach=0.002,
                   interaction=gfmd.Adhesive(1e-3, 0.05)).summary,
        gfmd.solve(top, gfmd.ElasticBody(), force=0.005, hardness=0.1).summary,
        gfmd.solve(top, gfmd.ViscoelasticBody(poisson=0.5, high_frequency_modulus=10.0, relaxation_time=1.0),
                   force=0.005, friction=0.3, velocity=0.05).summary,
        gfmd.solve(top, gfmd.ElasticBody(), force=0.005, friction=0.3,
                   indenter_body=gfmd.ElasticBody(contact_modulus=2.0)).summary,
        gfmd.run_toml("[grid]\nnx = 64\nlx = 1.0\n[indenter]\ntype = \"selfaffine\"\nlambda_short = 0.05\n"
                      "rms_gradient = 0.1\n[load]\npressure = 0.02\n[flow]\n")["summary"],
    ]
    documented = documented_keys()
    written = set().union(*(s.keys() for s in summaries))
    missing = sorted(k for k in written if k not in documented and not k.startswith("post_analysis_"))
    assert not missing, f"summary.json keys docs/summary.md does not name: {missing}"
    assert "relative_contact_area" in written and "hysteresis_friction" in written  # the runs ran their physics
