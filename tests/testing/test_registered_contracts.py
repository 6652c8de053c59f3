"""The public contract tests, run here over every plugin this installation registers."""

from graspframe.testing import contract_tests
from graspframe.testing.contract_tests import (  # noqa: F401 - collected by pytest
    test_arm_contract,
    test_backend_contract,
    test_classifier_contract,
    test_hand_alone_holds_its_design_objects,
    test_hand_closes_its_preshapes,
    test_hand_contract,
    test_hand_open_preshapes_are_free_of_self_collision,
    test_no_plugin_failed_to_load,
)


def test_every_contract_test_runs_here():
    public = {name for name in vars(contract_tests) if name.startswith("test_")}
    assert public <= set(globals()), f"not run here: {sorted(public - set(globals()))}"
