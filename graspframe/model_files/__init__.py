"""Model files as every tool loads them: URDF elements, the kinematic tree, the URDF text
in memory (`urdf_model`), meshes as convex pieces (`convex`) and a mesh object's geometry
(`mesh_geometry`). Nothing here knows a hand from an arm."""
