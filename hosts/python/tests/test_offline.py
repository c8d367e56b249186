"""The offline tools through the C ABI (libfacerig_offline): the built-in head, conversion, a photo
head from Debian's astronaut portrait, and (shared data) a build on an ICT-FaceKit identity; each
returns the command's JSON report; progress is reported and can cancel; bad options raise."""
import json
import os

import pytest

import facerig
from facerig import offline


def test_default_head_reports_progress_and_its_report(tmp_path, head_path):
    stages = []
    report = offline.default_head(tmp_path / "head", progress=lambda stage, done, total: stages.append(stage))
    assert report["command"] == "default-head" and report["schema"] == 1
    assert [o["role"] for o in report["outputs"]][:2] == ["rig", "frig"]
    assert stages == ["build", "write"]
    made = facerig.Rig(tmp_path / "head" / "default_head.frig")
    built = facerig.Rig(head_path)
    assert report["result"]["vertices"] == made.vertex_count == built.vertex_count
    assert made.shape_names == built.shape_names


def test_cancel_from_progress_writes_nothing(tmp_path):
    out = tmp_path / "head"
    with pytest.raises(facerig.CancelledError, match="cancelled"):
        offline.default_head(out, progress=lambda stage, done, total: stage == "write")
    assert not (out / "default_head.frig").exists() and not (out / "default_head.glb").exists()


def test_an_exception_in_progress_stops_and_is_raised(tmp_path):
    def explode(stage, done, total):
        raise KeyError("from progress")
    with pytest.raises(KeyError, match="from progress"):
        offline.convert(os.environ["FACERIG_DEFAULT_HEAD"], tmp_path / "head.glb", progress=explode)
    assert not (tmp_path / "head.glb").exists()


def test_convert_and_its_report(tmp_path, head_path):
    report = offline.convert(head_path, tmp_path / "head.glb", json=tmp_path / "report.json")
    assert report == json.loads((tmp_path / "report.json").read_text())
    assert report["result"]["bytes"] == os.path.getsize(tmp_path / "head.glb")
    assert facerig.Rig(tmp_path / "head.glb").shape_count == report["result"]["shapes"]


def test_bad_options_raise_with_the_command_lines_message(tmp_path, head_path):
    with pytest.raises(facerig.InvalidArgumentError, match="convert"):
        offline.convert(head_path, tmp_path / "a.glb", no_such_option=True)
    with pytest.raises(facerig.FileError, match="missing.frig"):
        offline.convert(tmp_path / "missing.frig", tmp_path / "a.glb")


def test_a_photo_head_from_the_astronaut(tmp_path):
    portrait = os.environ.get("FACERIG_PORTRAIT")
    assert portrait, "no portrait: install python3-skimage (astronaut.png)"
    stages = []
    report = offline.photo(portrait, output=tmp_path / "astronaut.glb", frig=tmp_path / "astronaut.frig",
                           progress=lambda stage, done, total: stages.append(stage))
    assert report["command"] == "photo"
    assert {"read", "detect", "fit", "texture", "write"} <= set(stages)
    rig = facerig.Rig(tmp_path / "astronaut.frig")
    assert rig.shape_count > 50 and rig.has_uvs
    character = facerig.Character(rig)
    character.speak(facerig.Speech.from_track('{"version": 1, "language": "en-us", '
                                              '"phonemes": [{"start": 0.1, "duration": 0.2, "symbol": "A:"}]}'))
    assert character.update(0.2).max() > 0.1  # the photo head talks


@pytest.mark.shared_data
def test_a_build_on_an_ict_identity(tmp_path):
    ict = os.environ["FACERIG_ICT_DIR"]
    stages = []
    report = offline.build(template=ict, target=os.path.join(ict, "identity005.obj"), output=tmp_path / "id5.glb",
                           progress=lambda stage, done, total: stages.append(stage))
    assert report["command"] == "build"
    assert "register" in stages and "transfer" in stages
    rig = facerig.Rig(tmp_path / "id5.glb")
    assert rig.shape_count == report["result"]["shapes"] and rig.shape_count > 50
