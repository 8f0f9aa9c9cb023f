"""A learned kind trained at most learned_steps_limit steps, under its own name; other kinds untouched."""

from heatdata.descriptors import DescriptorSpec
from heatdata.experiments.describe import capped_steps


def test_only_a_kind_with_steps_beyond_the_limit_is_capped():
    pointnet = DescriptorSpec("pointnet", color="none")
    capped = capped_steps(pointnet, 100)
    assert capped.get("steps") == 100 and capped.get("color") == "none" and pointnet.get("steps") == 3000
    assert capped_steps(pointnet, 0) is pointnet and capped_steps(pointnet, 5000) is pointnet
    hgd = DescriptorSpec("hgd")
    assert capped_steps(hgd, 100) is hgd
