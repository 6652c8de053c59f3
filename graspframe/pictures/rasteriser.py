"""Headless CPU rendering with moderngl (EGL on Mesa llvmpipe; no GPU needed).

Geometry is given in the OpenCV camera frame (x right, y down, z forward [m]); the
projection maps pixel rows straight to framebuffer rows, so the (bottom-up) readback
needs no flip. Shading: Lambert with one directional light, ambient light and a weak
Blinn-Phong highlight; rendered at `SUPERSAMPLE` times the size and averaged down
(anti-aliasing). The background is composited afterwards from the alpha coverage.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

import cv2
import numpy as np
from numpy.typing import NDArray

from graspframe.common.camera import Camera
from graspframe.common.errors import GraspframeError

if TYPE_CHECKING:
    import moderngl

SUPERSAMPLE = 2
NEAR, FAR = 0.02, 10.0  # [m] clipping planes

_VERTEX_SHADER = """
#version 330
uniform mat4 projection;
in vec3 in_position;
in vec3 in_normal;
in vec3 in_albedo;
out vec3 v_normal;
out vec3 v_albedo;
out vec3 v_position;
void main() {
    v_normal = in_normal;
    v_albedo = in_albedo;
    v_position = in_position;
    gl_Position = projection * vec4(in_position, 1.0);
}
"""

_FRAGMENT_SHADER = """
#version 330
uniform vec3 light_dir;      // unit, towards the light, camera frame
uniform vec3 light_colour;
uniform float ambient;
uniform float specular;
in vec3 v_normal;
in vec3 v_albedo;
in vec3 v_position;
out vec4 f_colour;
void main() {
    vec3 n = normalize(v_normal);
    vec3 to_eye = normalize(-v_position);
    if (dot(n, to_eye) < 0.0) n = -n;
    float diffuse = max(dot(n, light_dir), 0.0);
    vec3 h = normalize(light_dir + to_eye);
    float spec = specular * pow(max(dot(n, h), 0.0), 24.0);
    vec3 rgb = v_albedo * (ambient + (1.0 - ambient) * diffuse) * light_colour + spec;
    f_colour = vec4(clamp(rgb, 0.0, 1.0), 1.0);
}
"""


class RenderError(GraspframeError):
    """The CPU renderer cannot start (no EGL / OpenGL 3.3 available)."""


def projection(camera: Camera) -> NDArray[np.float32]:
    """Clip matrix from OpenCV camera coordinates; NDC y grows with the pixel row."""
    w, h, n, f = camera.width, camera.height, NEAR, FAR
    P = np.array(
        [
            [2 * camera.fx / w, 0, 2 * camera.cx / w - 1, 0],
            [0, 2 * camera.fy / h, 2 * camera.cy / h - 1, 0],
            [0, 0, (f + n) / (f - n), -2 * f * n / (f - n)],
            [0, 0, 1, 0],
        ]
    )
    return P.astype(np.float32)


@dataclass(frozen=True)
class Lighting:
    """light_dir: unit vector towards the light in the camera frame; light_colour: RGB
    in [0, 1]; ambient: share of unlit brightness [0, 1]; specular: highlight strength."""

    light_dir: tuple[float, float, float] = (0.3, -0.5, -0.8)
    light_colour: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ambient: float = 0.45
    specular: float = 0.08


class Renderer:
    """One OpenGL context per process; `render` draws coloured triangles to a BGR image.

    Set LP_NUM_THREADS=1 before the first Renderer of a worker process when running one
    process per core (llvmpipe otherwise starts a thread per core in each).
    """

    def __init__(self, max_triangles: int = 200_000):
        import moderngl

        try:
            # moderngl's stub types each keyword setting as a dict; backend is a string.
            self.ctx = moderngl.create_standalone_context(backend="egl")  # type: ignore[arg-type]
        except Exception as exc:  # no EGL: try the platform default
            try:
                self.ctx = moderngl.create_standalone_context()
            except Exception:
                raise RenderError(f"cannot create an OpenGL 3.3 context: {exc}") from exc
        self.program = self.ctx.program(
            vertex_shader=_VERTEX_SHADER, fragment_shader=_FRAGMENT_SHADER
        )
        self._capacity = 3 * max_triangles
        self.vbo = self.ctx.buffer(reserve=self._capacity * 9 * 4)
        self.vao = self.ctx.vertex_array(
            self.program, [(self.vbo, "3f 3f 3f", "in_position", "in_normal", "in_albedo")]
        )
        self._fbo: moderngl.Framebuffer | None = None
        self._fbo_size = (0, 0)

    def _framebuffer(self, width: int, height: int) -> moderngl.Framebuffer:
        if self._fbo is not None and self._fbo_size == (width, height):
            return self._fbo
        if self._fbo is not None:
            self._fbo.release()
        self._fbo = self.ctx.simple_framebuffer((width, height), components=4)
        self._fbo_size = (width, height)
        return self._fbo

    def _draw(self, camera: Camera, n: int) -> moderngl.Framebuffer:
        """Rasterise the first `n` vertices of the buffer into a cleared framebuffer of
        the camera's size, with depth testing (both faces drawn)."""
        fbo = self._framebuffer(camera.width, camera.height)
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.ctx.enable(self.ctx.DEPTH_TEST)
        self.ctx.disable(self.ctx.CULL_FACE)
        self.vao.render(vertices=n)
        return fbo

    def _uniform(self, name: str) -> moderngl.Uniform:
        """A uniform of the shader program (the shaders above declare each one)."""
        return cast("moderngl.Uniform", self.program[name])

    def render(
        self,
        camera: Camera,
        positions: NDArray[np.float32],
        normals: NDArray[np.float32],
        albedo: NDArray[np.float32],
        lighting: Lighting,
    ) -> tuple[NDArray[np.uint8], NDArray[np.float32]]:
        """Draw triangles given in the camera frame [m] with per-vertex albedo RGB [0, 1].

        Returns (image BGR uint8 H x W x 3 on black, coverage alpha H x W in [0, 1]).
        """
        n = len(positions)
        if n > self._capacity:
            raise RenderError(f"{n // 3} triangles exceed the renderer's {self._capacity // 3}")
        ss = SUPERSAMPLE
        big = Camera(
            camera.width * ss,
            camera.height * ss,
            camera.fx * ss,
            camera.fy * ss,
            camera.cx * ss,
            camera.cy * ss,
        )
        data = np.concatenate([positions, normals, albedo], axis=1).astype(np.float32)
        self.vbo.write(data.tobytes())
        self._uniform("projection").write(projection(big).T.copy().tobytes())
        light = np.asarray(lighting.light_dir, dtype=np.float32)
        self._uniform("light_dir").value = tuple(light / np.linalg.norm(light))
        self._uniform("light_colour").value = tuple(lighting.light_colour)
        self._uniform("ambient").value = float(lighting.ambient)
        self._uniform("specular").value = float(lighting.specular)
        fbo = self._draw(big, n)
        raw = np.frombuffer(fbo.read(components=4), dtype=np.uint8)
        rgba = raw.reshape(big.height, big.width, 4).astype(np.float32)
        small = cv2.resize(rgba, (camera.width, camera.height), interpolation=cv2.INTER_AREA)
        bgr = np.clip(small[..., 2::-1] + 0.5, 0, 255).astype(np.uint8)
        alpha = small[..., 3] / 255.0
        return bgr, alpha.astype(np.float32, copy=False)

    def depth(self, camera: Camera, positions: NDArray[np.float32]) -> NDArray[np.float32]:
        """The distance along the optical axis [m] (the camera frame's z) of the nearest
        triangle at each pixel centre, H x W, +inf where no triangle covers it; triangles
        given in the camera frame [m]. One sample per pixel, as a depth sensor measures."""
        n = len(positions)
        if n > self._capacity:
            raise RenderError(f"{n // 3} triangles exceed the renderer's {self._capacity // 3}")
        data = np.zeros((n, 9), dtype=np.float32)
        data[:, :3] = positions
        data[:, 5] = 1.0  # any normal: only the depth buffer is read
        self.vbo.write(data.tobytes())
        self._uniform("projection").write(projection(camera).T.copy().tobytes())
        fbo = self._draw(camera, n)
        raw = np.frombuffer(fbo.read(components=1, attachment=-1, dtype="f4"), dtype=np.float32)
        window = raw.reshape(camera.height, camera.width).astype(np.float64)
        # Window depth [0, 1] -> NDC [-1, 1] -> the camera's z, with projection()'s planes.
        z_ndc = 2.0 * window - 1.0
        z = 2.0 * FAR * NEAR / ((FAR + NEAR) - z_ndc * (FAR - NEAR))
        z[window >= 1.0] = np.inf
        return z.astype(np.float32)

    def release(self) -> None:
        self.ctx.release()


def composite(foreground_bgr, alpha, background_bgr) -> NDArray[np.uint8]:
    """Blend a rendered image (premultiplied by its coverage alpha [0, 1], as `render`
    returns it) over a background."""
    a = alpha[..., None]
    out = foreground_bgr.astype(np.float32) + background_bgr.astype(np.float32) * (1 - a)
    return np.clip(out + 0.5, 0, 255).astype(np.uint8)


def single_thread_llvmpipe() -> None:
    """Ask llvmpipe for one render thread (call before the first context of a process)."""
    os.environ.setdefault("LP_NUM_THREADS", "1")
