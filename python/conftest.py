import pytest


@pytest.fixture(autouse=True)
def _doctest_namespace(doctest_namespace):
    import certmesh
    import numpy

    doctest_namespace["certmesh"] = certmesh
    doctest_namespace["np"] = numpy
