"""Band masks: parsing, what they keep, masks that leave nothing to fit."""

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.retrieval import BandMask


def test_masks_parse_and_keep():
    wl = np.array([900.0, 950.0, 1000.0, 1400.0, 1500.0])
    assert BandMask.parse("water-vapour").keep(wl).tolist() == [True, False, True, False, True]
    assert BandMask.parse("940-960, 1390-1410").keep(wl).tolist() == [True, False, True, False, True]
    assert BandMask.parse(None).keep(wl).all()
    assert BandMask.parse([(1450, 1550)]).keep(wl).tolist() == [True, True, True, True, False]


@pytest.mark.parametrize("mask", ["1400", "a-b", [(1500, 1400)], [(1, 2, 3)], [(np.nan, 5)]])
def test_bad_masks_are_named(mask):
    with pytest.raises(ParameterError, match="mask"):
        BandMask.parse(mask)


def test_masked_wavelengths_are_not_fitted(dry_spectrum):
    result = sandlight.fit(dry_spectrum, ["iron_oxide"], {"saturation": 0.0}, mask="590-710", noise=0.002, check_rays=0)
    assert result.observation.centres_nm.max() == 580
    with pytest.raises(ParameterError, match="left to fit"):
        sandlight.fit(dry_spectrum, ["iron_oxide"], {"saturation": 0.0}, mask="390-690", noise=0.002)
