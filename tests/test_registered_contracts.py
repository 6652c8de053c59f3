"""The public contract tests, run here over every plugin this installation registers."""

from graspframe.testing.contract_tests import (  # noqa: F401 - collected by pytest
    test_arm_contract,
    test_backend_contract,
    test_classifier_contract,
    test_hand_contract,
    test_no_plugin_failed_to_load,
)
