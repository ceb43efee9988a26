from ohm_mirror_detector3d.labels import KEPT_IN_CLEANED, Label


def test_label_values_match_the_design_contract():
    assert [int(label) for label in Label] == list(range(10))
    assert Label.ERROR not in KEPT_IN_CLEANED and Label.NAN_POINT not in KEPT_IN_CLEANED


def test_design_names_match_the_cpp_core():
    assert Label.ERROR_SURFACE.design_name == 'errorSurface'
    assert Label.BEHIND_ERROR_S.design_name == 'behindErrorS'
    assert Label.NAN_POINT.design_name == 'nanPoint'
