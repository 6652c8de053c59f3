"""Pictures of robots, objects and contacts, rendered on the CPU.

- `meshes.py`: a robot model's display meshes per link (the vendor's visual meshes,
  decoded and decimated once per process, and the collision shapes), in link frames;
- `render3d.py`: meshes placed in the world -> shaded views (graspframe/pictures/rasteriser.py's
  rasteriser, one per process), cameras, projecting points into a view;
- `style.py`: the colours every picture shares (real fingers, arm, object, table,
  contacts, palm axes);
- `robot_scene.py`: a robot posed by forward kinematics as meshes to render, with the
  object and the table;
- `panel.py`: one rendered view with the contacts and the palm axes drawn on top, and
  the legend of a grasp picture;
- `sheet.py`: panels, captions and a legend composed into one PNG (text by Pillow,
  markers by OpenCV), written atomically;
- `inputs.py`: checks of what the picture functions are given (one-line InputErrors);
- `hand_grasp.py`: `draw_hand_grasp`, one hand closed around an object (check-hand).

`graspframe/pictures/snapshots.py` (the run's snapshots.png) is built from the same parts.
"""
