"""Common types and I/O, the floor every other package stands on.

`errors` (the one exception root and its exit codes), `transforms` (poses and rotations,
`T_a_b`), `grasps` (the six human grasps and preshape names), `contacts` (hand-object
contacts), `defaults` (the defaults defined once), `files` (writes a reader never sees
half done), `json_files` (JSON-safe values, reading and writing JSON files), `cache` (the
on-disk cache) and `moved_modules` (the module paths that moved, kept importable for a
deprecation period).
"""
