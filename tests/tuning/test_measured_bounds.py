"""A measured-modes file is bounded like an identified-modes file (bearingfw.oma.io): frequencies,
shape values and the text encoding are refused with the field or line named."""

import pytest

from bearingfw.oma.io import MAX_FREQUENCY, MAX_SHAPE
from bearingfw.parameters import ParameterError
from bearingfw.tuning.measured import read_measured


def _write(tmp_path, text: str, name: str = "modes.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_a_frequency_above_the_bound_is_refused_naming_the_field(tmp_path):
    path = _write(tmp_path, f'[[modes]]\nfrequency = {MAX_FREQUENCY * 10:g}\nlabel = "vertical 1"\n')
    with pytest.raises(ParameterError, match=r"mode 1: field 'frequency' must be > 0 Hz and at most 100000 Hz"):
        read_measured(path)


@pytest.mark.parametrize("shape", ['{ "GA1.uz" = 1e300, "GA2.uz" = 1.0 }', "[1e300, 1.0]"])
def test_a_huge_shape_value_is_refused_naming_it(tmp_path, shape):
    text = f'channels = ["GA1.uz", "GA2.uz"]\n[[modes]]\nfrequency = 1.5\nshape = {shape}\n'
    with pytest.raises(ParameterError, match=r"field 'shape(\.GA1\.uz|\[0\])' must be at most 1e\+30"):
        read_measured(_write(tmp_path, text))
    assert MAX_SHAPE == 1e30


def test_a_file_that_is_not_utf8_names_its_line(tmp_path):
    path = tmp_path / "modes.toml"
    path.write_bytes(b'[[modes]]\nfrequency = 1.5\nlabel = "vertical \xe91"\n')
    with pytest.raises(ParameterError, match=r"modes.toml: line 3 is not UTF-8"):
        read_measured(path)


def test_values_inside_the_bounds_are_read(tmp_path):
    text = 'channels = ["GA1.uz", "GA2.uz"]\n[[modes]]\nfrequency = 1.5\nshape = [1e29, -2.0]\n'
    modes = read_measured(_write(tmp_path, text))
    assert modes.measurements[0].frequency == 1.5
    assert modes.measurements[0].shape.tolist() == [1e29, -2.0]
