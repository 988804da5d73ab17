"""Progress lines of the lab protocols from Python: the lines the apps print (stage, strain, rate,
time left) go to Python's sys.stdout by default, to a callable, or nowhere (progress=False, or
quiet=True as before); an exception the callable raises stops the stage at that line and comes out
of the stage's call; a bad progress argument is refused with a message naming it."""

import pytest

import libdem
from conftest import REDUCED

EVERY_LINE = dict(REDUCED, output={"progress_seconds": 1e-9}, shear={"target_strain": 0.01})
BALLS = 155  # the reduced 4D cell at the preset's porosity 0.46: the generation's first line names it


def test_a_callable_gets_each_progress_line_of_every_stage(tmp_path):
    lines = []
    test = libdem.SimpleShear(EVERY_LINE, out=tmp_path, preset="4D", progress=lines.append)
    test.run()
    assert lines and all(isinstance(line, str) and "\n" not in line for line in lines)
    assert lines[0].startswith(f"generation: {BALLS} balls")
    for stage in ("[generation] ", "[consolidation] ", "[shear] strain "):
        assert any(line.startswith(stage) for line in lines), stage
    shear = [line for line in lines if line.startswith("[shear]")]
    assert all(" of 0.01, " in line and "particle-steps/s" in line and line.endswith(" s left") for line in shear)
    assert lines[-1].startswith("shear done in ")


def test_progress_goes_to_sys_stdout_by_default_and_nowhere_when_quiet(tmp_path, capsys):
    libdem.SimpleShear(EVERY_LINE, out=tmp_path / "default", preset="4D").generate()
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].startswith(f"generation: {BALLS} balls") and printed[-1].startswith("generation done in ")
    libdem.SimpleShear(EVERY_LINE, out=tmp_path / "quiet", preset="4D", quiet=True).generate()
    libdem.SimpleShear(EVERY_LINE, out=tmp_path / "off", preset="4D", progress=False).generate()
    assert capsys.readouterr().out == ""


def test_an_exception_from_the_callable_stops_the_stage_and_the_next_call_goes_on(tmp_path):
    lines = []

    def stop_once(line):
        if not lines:
            lines.append("stopped")
            raise KeyboardInterrupt  # as Ctrl-C at a progress line
        lines.append(line)

    test = libdem.SimpleShear(EVERY_LINE, out=tmp_path, preset="4D", progress=stop_once)
    with pytest.raises(KeyboardInterrupt):
        test.generate()  # at its first line, before any ball
    assert test.stage == 0 and (test.world.clump_of >= 0).all()  # the rings' pebbles, no ball yet
    test.generate()
    assert test.stage == 1 and test.ball_count == BALLS
    assert lines[1].startswith(f"generation: {BALLS} balls") and lines[-1].startswith("generation done in ")


def test_a_bad_progress_argument_is_refused_naming_it(tmp_path):
    with pytest.raises(ValueError, match=r"^SimpleShear progress = 'yes': must be True .*False .*None .*or a callable"):
        libdem.SimpleShear(REDUCED, out=tmp_path, preset="4D", progress="yes")
    with pytest.raises(ValueError, match=r"^SimpleShear progress = True with quiet = True: must be False or None"):
        libdem.SimpleShear(REDUCED, out=tmp_path, preset="4D", quiet=True, progress=True)
    specimen = libdem.SimpleShear(REDUCED, out=tmp_path, preset="4D", quiet=True)
    with pytest.raises(ValueError, match=r"^CyclicShear progress = 3: must be True"):
        libdem.CyclicShear(specimen, {}, progress=3)
