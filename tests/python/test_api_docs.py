"""The module explains itself: every public class, function, property and enum value has a
docstring of its own, help() on a method gives what it does and its arguments with their units, and
the type stubs written beside the module (python/stubgen.py, libdem.pyi) define every public name."""

import pydoc
from pathlib import Path

import libdem
from api_names import missing_from_stubs, undocumented


def test_every_public_name_has_a_docstring():
    assert undocumented(libdem) == []


def test_help_of_a_method_says_what_it_does_and_its_arguments_with_units():
    text = pydoc.render_doc(libdem.World.step, renderer=pydoc.plaintext)
    assert "step(self: libdem.World, n: int = 1) -> None" in text
    assert "Advances the simulation by n time steps" in text and "n: steps to take" in text
    text = pydoc.render_doc(libdem.World.add_ball, renderer=pydoc.plaintext)
    for argument in ("position: centre (m)", "radius: (m)", "density: (kg/m^3)", "velocity: (m/s)"):
        assert argument in text


def test_the_stubs_beside_the_module_define_every_public_name():
    stubs = Path(libdem.__file__).with_name("libdem.pyi")
    public, missing = missing_from_stubs(libdem, stubs.read_text())
    assert len(public) > 300 and missing == []
    compile(stubs.read_text(), str(stubs), "exec")
