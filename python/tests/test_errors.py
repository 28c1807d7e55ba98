"""Bad input raises effigi.Error (a RuntimeError) naming the file and line, as the CLI says."""
import pytest

import effigi


def test_error_is_a_runtime_error():
    assert issubclass(effigi.Error, RuntimeError)


def test_unknown_parameter_names_file_and_line(tmp_path):
    scene = tmp_path / "bad.xml"
    scene.write_text("""<scene version="3.0.0">
    <sensor type="perspective">
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
    <shape type="sphere">
        <float name="radiuss" value="1"/>
    </shape>
</scene>
""")
    with pytest.raises(effigi.Error, match=rf"{scene}:6: .*radiuss"):
        effigi.load_file(scene)


def test_malformed_xml_in_a_string_names_its_line():
    with pytest.raises(effigi.Error, match=r"<string>:\d+: malformed XML"):
        effigi.load_string('<scene version="3.0.0">\n<shape type="sphere">\n</scene>\n')


def test_missing_file_and_undeclared_variable():
    with pytest.raises(effigi.Error, match="nope.xml"):
        effigi.load_file("nope.xml")
    with pytest.raises(effigi.Error, match=r"<string>:1: .*\$radius"):
        effigi.load_string('<scene version="3.0.0"><shape type="sphere"><float name="radius" value="$radius"/>'
                           '</shape></scene>')
