import sandlight
from sandlight import _native


def test_native_extension_matches_package_version():
    assert _native.__version__ == sandlight.__version__
