"""The KUKA KR 5 sixx R850 arm (6 DOF), the arm of the original real-robot demo."""
