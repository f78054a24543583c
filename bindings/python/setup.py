"""The wheel holds a native module (_acuity, built by CMake, not by setuptools): tagged for this
Python and platform rather than as pure Python. Metadata: pyproject.toml."""
from setuptools import setup
from setuptools.dist import Distribution


class BinaryDistribution(Distribution):
    def has_ext_modules(self):
        return True


setup(distclass=BinaryDistribution)
