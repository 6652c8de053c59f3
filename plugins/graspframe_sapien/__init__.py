"""Built-in graspframe plugin: the SAPIEN physics backend (CPU physics, no renderer)."""

import warnings

# Only physics is used, which needs no Vulkan; SAPIEN's notice that it falls back to its
# bundled libvulkan is noise on a machine without a GPU.
warnings.filterwarnings("ignore", message="Failed to find system libvulkan")
