"""The KUKA LBR iiwa 14 R820 arm (7 DOF), a second arm to prove the arm interface."""
