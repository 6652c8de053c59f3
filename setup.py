"""Package layout (metadata lives in pyproject.toml).

One wheel carries the core (`graspframe/`), every built-in plugin (each folder under
`plugins/` is a top-level package) and the model files of `robots/`, installed as the
package `graspframe_robots`.
"""

from setuptools import find_packages, setup

core = find_packages(".", include=["graspframe", "graspframe.*"])
plugins = find_packages("plugins")
package_dir = {name: f"plugins/{name.replace('.', '/')}" for name in plugins}
package_dir["graspframe_robots"] = "robots"

setup(packages=[*core, *plugins, "graspframe_robots"], package_dir=package_dir)
