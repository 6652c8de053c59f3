"""Names vulture reports as unused that are used: read by tests, documentation or other
libraries, or part of a plugin-facing interface. Vulture only parses this file; nothing
here runs. Typer commands, pluggy hooks and the recording's `_on_<event>` handlers are
excluded in [tool.vulture] (pyproject.toml) by decorator and name pattern."""

import coal
import faiss
import ruckig
import sapien
from graspframe_hog_knn.demo import write_demo
from graspframe_hog_knn.segmentation import HandCrop
from graspframe_human.description import HAND_LENGTH
from graspframe_karlsruhe.description import MODEL_FRAME
from graspframe_landmarks.features import FEATURE_NAMES
from graspframe_sapien.drivers import SapienHandDriver
from graspframe_sapien.world import SapienWorld

from graspframe.common.grasps import HumanGrasp
from graspframe.hal.descriptions import HandDescription
from graspframe.hal.objects import ObjectDescription
from graspframe.metrics.virtual_fingers import MatchedPair, VirtualFingerGrasp
from graspframe.model_files.convex import ConvexPieces
from graspframe.model_files.mesh_geometry import MeshGeometry
from graspframe.motion.arm_motion import LinearMoveResult
from graspframe.motion.ik import IkSolver
from graspframe.plugin_system.hookspecs import Register
from graspframe.plugin_system.registry import Registry
from graspframe.robot_models import floating_base
from graspframe.robot_models.model import CollisionModel

# Attributes that other libraries read once set.
ruckig.InputParameter.duration_discretization
ruckig.InputParameter.control_interface
ruckig.InputParameter.current_position
ruckig.InputParameter.current_velocity
ruckig.InputParameter.current_acceleration
ruckig.InputParameter.target_position
ruckig.InputParameter.target_velocity
ruckig.InputParameter.target_acceleration
faiss.IndexHNSW.efConstruction
faiss.IndexHNSW.efSearch
coal.CollisionRequest.security_margin
sapien.physx.PhysxRigidDynamicComponent.max_depenetration_velocity
sapien.physx.PhysxRigidDynamicComponent.cmass_local_pose
MeshGeometry.upright_as_scanned  # read by the tests: the rest pose a person finds
coal.DistanceRequest.enable_signed_distance
sapien.URDFLoader.fix_root_link
sapien.physx.PhysxArticulationLinkComponent.disable_gravity

# Data fields of descriptions and results: part of what they describe.
HandDescription.extras
ObjectDescription.extras
LinearMoveResult.T_world_palm_at_contact
LinearMoveResult.T_world_palm_end
LinearMoveResult.travel_after_contact
MatchedPair.robot_index
MatchedPair.human_index
HandCrop.area

# Interfaces: the plugin callback protocol.
Register.__call__

# SAPIEN's URDF loader reads these while parsing model text (graspframe_sapien.articulation).
sapien.wrapper.urdf_loader.URDFLoader.package_dir
sapien.wrapper.urdf_loader.URDFLoader.ignore_pairs

# Public helpers the tests use and the documentation names.
ConvexPieces.method
HumanGrasp.cutkosky_number
HumanGrasp.volar_for_human
VirtualFingerGrasp.touching_real_fingers
IkSolver.hand_q_in_model
Registry.add_plugin
CollisionModel.colliding_links
floating_base.PALM_POSITION_ACCURACY  # the accuracy it states, measured by a test
floating_base.PALM_ORIENTATION_ACCURACY
SapienHandDriver.held_leaders
SapienWorld.teleport_hand
FEATURE_NAMES
write_demo

# Facts of a hand model the tests check it against: the human hand's chosen size, the
# Karlsruhe hand's frame of the published kinematics.
HAND_LENGTH
MODEL_FRAME

# The run-event catalogue: its list and the prose of each kind and field are read by the
# documentation test and by observers.
from graspframe.plugin_system import events  # noqa: E402

events.EVENT_KINDS
events.EventKind.when
events.PayloadField.meaning

# A trial's numbers that only its trials.jsonl line carries (to_json reads every field).
from graspframe.experiments.trials import TrialRow  # noqa: E402

TrialRow.score_error
TrialRow.limit_excess_deg
TrialRow.limit_violations

# A plan's field that only result.json shows (json_files.jsonable writes every field).
from graspframe.strategy.planner import GraspPlan  # noqa: E402

GraspPlan.standoff

# The import system calls these (the finder that keeps moved module paths importable).
from graspframe.common import moved_modules  # noqa: E402

moved_modules._MovedModuleLoader.create_module
moved_modules._MovedModuleLoader.exec_module
moved_modules._MovedModuleFinder.find_spec
