"""The registry and the conformance suites from Python."""
import pytest

import effigi


def test_components_lists_tag_slash_name():
    names = effigi.components()
    assert "bsdf/diffuse" in names and "renderer/path" in names
    assert all(n.count("/") == 1 for n in names)
    assert names == sorted(names)


def test_info_is_the_schema():
    d = effigi.info("bsdf/diffuse")
    assert (d["tag"], d["name"]) == ("bsdf", "diffuse")
    assert d["doc"]
    reflectance = {p["name"]: p for p in d["parameters"]}["reflectance"]
    assert reflectance["type"] in ("spectrum", "texture")
    film = {p["name"]: p for p in effigi.info("film/hdrfilm")["parameters"]}
    assert film["width"]["default"] == 768 and film["width"]["type"] == "integer"
    assert "xyz" in film["pixel_format"]["choices"]
    with pytest.raises(effigi.Error, match="nope"):
        effigi.info("bsdf/nope")
    with pytest.raises(effigi.Error, match="tag/name"):
        effigi.info("diffuse")


def test_conformance_report_of_one_component(tmp_path):
    report = effigi.conform("sampler/independent", out_dir=tmp_path)
    assert report["failed"] == 0
    assert report["passed"] > 0 and report["passed"] + report["skipped"] + report["info"] == len(report["rows"])
    row = report["rows"][0]
    assert {"tag", "component", "config", "check", "verdict", "figure", "p_value", "detail"} <= row.keys()
    assert {r["component"] for r in report["rows"]} == {"independent"}
    assert {r["verdict"] for r in report["rows"]} <= {"PASS", "SKIP", "INFO"}
    with pytest.raises(effigi.Error, match="no conformance suite for tag 'nope'"):
        effigi.conform("nope/independent")
    with pytest.raises(effigi.Error, match="no component matches"):
        effigi.conform("sampler/nope")
