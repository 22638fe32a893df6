import pytest
from motion_records import CHUETSU, MANJIL


@pytest.fixture(scope="session")
def chuetsu():
    from bearingfw.motion import read_record

    return read_record(CHUETSU)


@pytest.fixture(scope="session")
def manjil():
    from bearingfw.motion import read_record

    return read_record(MANJIL)
