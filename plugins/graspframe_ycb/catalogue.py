"""The YCB Object and Model Set: every object of the set with its published mass and
the grasp a person would use on it as it lies on the table.

Masses: B. Calli, A. Walsman, A. Singh, S. Srinivasa, P. Abbeel, A. M. Dollar,
"Benchmarking in Manipulation Research: The YCB Object and Model Set and Benchmarking
Protocols", IEEE Robotics & Automation Magazine 22(3), 2015, Table 1 (the object list of
ycbbenchmarks.com gives the same values but for seven: padlock 208 g, keys 6 g,
bolt 5.9 g, nut 3.4 g, baseball 138 g, chain 100 g, timer 101 g; the paper's are used).
The paper gives no mass for the parts of three objects, only for the assembled set:
the marbles (none), the toy airplane's parts (570 g assembled) and the Lego Duplo pieces
(`UNWEIGHED`): they are found but not registered unless a sidecar gives their mass.

The grasps are our reading of how a person picks each object up from the table with
one hand (docs/objects.md): the Cutkosky types the method knows (a handle is held by
its handle, flat things lying on the table with a pinch, balls with a power sphere).
The folder names are those of the set's download (`<id>_<name>`).
"""

from __future__ import annotations

from typing import NamedTuple

from graspframe.common.grasps import HumanGrasp

LARGE_DIAMETER = HumanGrasp.LARGE_DIAMETER
SMALL_DIAMETER = HumanGrasp.SMALL_DIAMETER
PINCH = HumanGrasp.PINCH
POWER_SPHERE = HumanGrasp.POWER_SPHERE
PRECISION_DISC = HumanGrasp.PRECISION_DISC


class YcbObject(NamedTuple):
    """mass: [kg] (Calli et al. 2015, Table 1); grasp: what a person would use; summary:
    one line (the object and its published size)."""

    mass: float
    grasp: HumanGrasp
    summary: str


YCB_OBJECTS: dict[str, YcbObject] = {
    "001_chips_can": YcbObject(0.205, LARGE_DIAMETER, "a Pringles chips can, 75 x 250 mm"),
    "002_master_chef_can": YcbObject(0.414, LARGE_DIAMETER, "a coffee can, 102 x 139 mm"),
    "003_cracker_box": YcbObject(0.411, LARGE_DIAMETER, "a cracker box, 60 x 158 x 210 mm"),
    "004_sugar_box": YcbObject(0.514, LARGE_DIAMETER, "a sugar box, 38 x 89 x 175 mm"),
    "005_tomato_soup_can": YcbObject(0.349, LARGE_DIAMETER, "a soup can, 66 x 101 mm"),
    "006_mustard_bottle": YcbObject(0.603, LARGE_DIAMETER, "a mustard bottle, 58 x 95 x 190 mm"),
    "007_tuna_fish_can": YcbObject(0.171, PRECISION_DISC, "a tuna can lying flat, 85 x 33 mm"),
    "008_pudding_box": YcbObject(0.187, PINCH, "a pudding box, 35 x 110 x 89 mm"),
    "009_gelatin_box": YcbObject(0.097, PINCH, "a gelatin box, 28 x 85 x 73 mm"),
    "010_potted_meat_can": YcbObject(0.37, LARGE_DIAMETER, "a potted meat can, 50 x 97 x 82 mm"),
    "011_banana": YcbObject(0.066, PINCH, "a plastic banana lying on its side, 36 x 190 mm"),
    "012_strawberry": YcbObject(0.018, PINCH, "a plastic strawberry, 44 x 55 mm"),
    "013_apple": YcbObject(0.068, POWER_SPHERE, "a plastic apple, 75 mm"),
    "014_lemon": YcbObject(0.029, POWER_SPHERE, "a plastic lemon, 54 x 68 mm"),
    "015_peach": YcbObject(0.033, POWER_SPHERE, "a plastic peach, 59 mm"),
    "016_pear": YcbObject(0.049, POWER_SPHERE, "a plastic pear, 66 x 100 mm"),
    "017_orange": YcbObject(0.047, POWER_SPHERE, "a plastic orange, 73 mm"),
    "018_plum": YcbObject(0.025, POWER_SPHERE, "a plastic plum, 52 mm"),
    "019_pitcher_base": YcbObject(0.178, LARGE_DIAMETER, "a pitcher, 108 x 235 mm"),
    "021_bleach_cleanser": YcbObject(
        1.131, LARGE_DIAMETER, "a bleach cleanser bottle, 250 x 98 x 65 mm"
    ),
    "022_windex_bottle": YcbObject(1.022, LARGE_DIAMETER, "a spray bottle, 80 x 105 x 270 mm"),
    "023_wine_glass": YcbObject(
        0.133, SMALL_DIAMETER, "a wine glass held by its stem, 89 x 137 mm"
    ),
    "024_bowl": YcbObject(0.147, PRECISION_DISC, "a bowl, 159 x 53 mm"),
    "025_mug": YcbObject(0.118, LARGE_DIAMETER, "a mug with a handle, 80 x 82 mm"),
    "026_sponge": YcbObject(0.0062, PINCH, "a sponge, 72 x 114 x 14 mm"),
    "027_skillet": YcbObject(0.95, SMALL_DIAMETER, "a skillet held by its handle"),
    "028_skillet_lid": YcbObject(0.652, PRECISION_DISC, "a skillet lid"),
    "029_plate": YcbObject(0.279, PRECISION_DISC, "a plate, 258 x 24 mm"),
    "030_fork": YcbObject(0.034, PINCH, "a fork, 198 mm"),
    "031_spoon": YcbObject(0.03, PINCH, "a spoon, 195 mm"),
    "032_knife": YcbObject(0.031, PINCH, "a knife, 215 mm"),
    "033_spatula": YcbObject(0.0515, PINCH, "a spatula, 350 mm"),
    "035_power_drill": YcbObject(0.895, LARGE_DIAMETER, "a power drill held by its grip"),
    "036_wood_block": YcbObject(0.729, LARGE_DIAMETER, "a wood block, 85 x 85 x 200 mm"),
    "037_scissors": YcbObject(0.082, PINCH, "scissors, 87 x 200 mm"),
    "038_padlock": YcbObject(0.304, PINCH, "a padlock, 24 x 47 x 65 mm"),
    "039_key": YcbObject(0.0101, PINCH, "keys, 23 x 43 mm"),
    "040_large_marker": YcbObject(0.0158, PINCH, "a marker lying down, 18 x 121 mm"),
    "041_small_marker": YcbObject(0.0082, PINCH, "a small marker lying down, 8 x 135 mm"),
    "042_adjustable_wrench": YcbObject(0.252, PINCH, "an adjustable wrench lying flat, 205 mm"),
    "043_phillips_screwdriver": YcbObject(0.097, PINCH, "a screwdriver lying down, 31 x 215 mm"),
    "044_flat_screwdriver": YcbObject(0.0984, PINCH, "a screwdriver lying down, 31 x 215 mm"),
    "046_plastic_bolt": YcbObject(0.0036, PINCH, "a plastic bolt, 43 mm"),
    "047_plastic_nut": YcbObject(0.001, PINCH, "a plastic nut, 16 mm"),
    "048_hammer": YcbObject(0.665, SMALL_DIAMETER, "a hammer held by its handle, 333 mm"),
    "049_small_clamp": YcbObject(0.0192, PINCH, "a small clamp"),
    "050_medium_clamp": YcbObject(0.059, PINCH, "a clamp, 90 x 115 mm"),
    "051_large_clamp": YcbObject(0.125, PINCH, "a clamp, 125 x 165 mm"),
    "052_extra_large_clamp": YcbObject(0.202, PINCH, "a clamp, 165 x 213 mm"),
    "053_mini_soccer_ball": YcbObject(0.123, POWER_SPHERE, "a mini soccer ball, 140 mm"),
    "054_softball": YcbObject(0.191, POWER_SPHERE, "a softball, 96 mm"),
    "055_baseball": YcbObject(0.148, POWER_SPHERE, "a baseball, 75 mm"),
    "056_tennis_ball": YcbObject(0.058, POWER_SPHERE, "a tennis ball, 65 mm"),
    "057_racquetball": YcbObject(0.041, POWER_SPHERE, "a racquetball, 55 mm"),
    "058_golf_ball": YcbObject(0.046, PINCH, "a golf ball, 43 mm"),
    "059_chain": YcbObject(0.098, PINCH, "a chain"),
    "061_foam_brick": YcbObject(0.028, PINCH, "a foam brick, 50 x 75 x 50 mm"),
    "062_dice": YcbObject(0.0052, PINCH, "a die, 16 mm"),
    "065-a_cups": YcbObject(0.013, LARGE_DIAMETER, "a stacking cup, 55 x 60 mm"),
    "065-b_cups": YcbObject(0.014, LARGE_DIAMETER, "a stacking cup, 60 x 62 mm"),
    "065-c_cups": YcbObject(0.017, LARGE_DIAMETER, "a stacking cup, 65 x 64 mm"),
    "065-d_cups": YcbObject(0.019, LARGE_DIAMETER, "a stacking cup, 70 x 66 mm"),
    "065-e_cups": YcbObject(0.021, LARGE_DIAMETER, "a stacking cup, 75 x 68 mm"),
    "065-f_cups": YcbObject(0.026, LARGE_DIAMETER, "a stacking cup, 80 x 70 mm"),
    "065-g_cups": YcbObject(0.028, LARGE_DIAMETER, "a stacking cup, 85 x 72 mm"),
    "065-h_cups": YcbObject(0.031, LARGE_DIAMETER, "a stacking cup, 90 x 74 mm"),
    "065-i_cups": YcbObject(0.035, LARGE_DIAMETER, "a stacking cup, 95 x 76 mm"),
    "065-j_cups": YcbObject(0.038, LARGE_DIAMETER, "a stacking cup, 100 x 78 mm"),
    "070-a_colored_wood_blocks": YcbObject(0.0108, PINCH, "a wooden cube, 26 mm"),
    "070-b_colored_wood_blocks": YcbObject(0.0108, PINCH, "a wooden cube, 26 mm"),
    "071_nine_hole_peg_test": YcbObject(
        1.435, LARGE_DIAMETER, "a nine-hole peg test board with its pegs"
    ),
    "076_timer": YcbObject(0.102, PRECISION_DISC, "a kitchen timer, 80 x 85 x 45 mm"),
    "077_rubiks_cube": YcbObject(0.094, PINCH, "a Rubik's cube, 57 mm"),
}

# The set's objects the paper gives no mass for (see the module docstring).
UNWEIGHED = (
    "063-a_marbles",
    "063-b_marbles",
    "063-c_marbles",
    "063-d_marbles",
    "063-e_marbles",
    "063-f_marbles",
    "072-a_toy_airplane",
    "072-b_toy_airplane",
    "072-c_toy_airplane",
    "072-d_toy_airplane",
    "072-e_toy_airplane",
    "072-f_toy_airplane",
    "072-g_toy_airplane",
    "072-h_toy_airplane",
    "072-i_toy_airplane",
    "072-j_toy_airplane",
    "072-k_toy_airplane",
    "073-a_lego_duplo",
    "073-b_lego_duplo",
    "073-c_lego_duplo",
    "073-d_lego_duplo",
    "073-e_lego_duplo",
    "073-f_lego_duplo",
    "073-g_lego_duplo",
    "073-h_lego_duplo",
    "073-i_lego_duplo",
    "073-j_lego_duplo",
    "073-k_lego_duplo",
    "073-l_lego_duplo",
    "073-m_lego_duplo",
)
