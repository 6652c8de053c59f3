"""The simulated depth camera: the world's geometry rendered on the CPU, with the noise
of a structured-light sensor of the Kinect class (graspframe/perception/depth_noise.py)."""
