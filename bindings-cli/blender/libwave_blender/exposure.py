"""The view's exposure metered as a camera meters a scene (docs/blender.md, "Exposure"):
a small Cycles render of the scene camera's view, its log-average luminance (the scene's
key: Reinhard et al. 2002, "Photographic tone reproduction") brought to middle grey by
the view's exposure. The physical sky's radiance is absolute, so one exposure cannot
suit a noon beach and a view into a sun 5° up: the first is metered a stop or two down,
the sunset four or five, as a photographer's camera would."""

import math
import os
import tempfile

import bpy
import numpy as np

MIDDLE_GREY = 0.18          # the key a meter brings the log-average luminance to
METER_PIXELS = 64           # the meter's image along its long side (pixels; the render's aspect kept)
METER_SAMPLES = 8           # Cycles' samples for it (noise averages out over the pixels)
EXPOSURE_RANGE = (-16.0, 16.0)  # stops: beyond them the picture is black or white whatever the meter says
_DELTA = 1e-4               # keeps log() finite on black pixels (Reinhard's δ)
# Rec. 709 luminance of Blender's scene-linear (Rec. 709 primaries) RGB.
_LUMA = np.array([0.2126, 0.7152, 0.0722], np.float64)


def log_average(rgb):
    """The log-average (geometric mean) luminance of an (n, 3) array of linear RGB."""
    luminance = np.maximum(np.asarray(rgb, np.float64) @ _LUMA, 0.0)
    return float(np.exp(np.mean(np.log(_DELTA + luminance))))


def exposure_for(key):
    """The view's exposure (stops) that brings a log-average luminance `key` to middle grey."""
    if not (key > 0.0) or not math.isfinite(key):
        return 0.0
    return min(max(math.log2(MIDDLE_GREY / key), EXPOSURE_RANGE[0]), EXPOSURE_RANGE[1])


def _settings(scene):
    r, c = scene.render, getattr(scene, "cycles", None)
    kept = {(r, name): getattr(r, name)
            for name in ("engine", "resolution_x", "resolution_y", "resolution_percentage", "filepath", "use_motion_blur",
                         "film_transparent", "use_border", "use_compositing", "use_sequencer")}
    for name in ("file_format", "color_mode", "color_depth"):
        kept[(r.image_settings, name)] = getattr(r.image_settings, name)
    if c is not None:
        for name in ("samples", "use_denoising", "use_adaptive_sampling"):
            if hasattr(c, name):
                kept[(c, name)] = getattr(c, name)
    return kept


def meter(context):
    """Meters the scene camera's view at the current frame and sets the view's exposure
    (scene.view_settings.exposure) to bring its log-average luminance to middle grey.
    Returns the exposure set, or None when the scene has no camera (nothing changed).
    The render's own settings are left as they were."""
    scene = context.scene
    if scene.camera is None:
        return None
    kept = _settings(scene)
    # The whitewater particles (thousands of instanced droplets and sheets) cost seconds
    # to build for a 64 × 36 image and weigh nothing in its mean: left out of it.
    for obj in scene.objects:
        if "libwave_whitewater" in obj and not obj.hide_render:
            kept[(obj, "hide_render")] = False
            obj.hide_render = True
    handle, path = tempfile.mkstemp(prefix="libwave-meter-", suffix=".exr")
    os.close(handle)
    image = None
    try:
        r = scene.render
        # The render's framing (its aspect, pixel aspect included) at METER_PIXELS on
        # the long side; the sky drawn (not a transparent film), the whole frame (no
        # border), the camera's own pixels (no compositor, no sequencer).
        wide = r.resolution_x * r.pixel_aspect_x >= r.resolution_y * r.pixel_aspect_y
        ratio = (r.resolution_y / max(r.resolution_x, 1)) if wide else (r.resolution_x / max(r.resolution_y, 1))
        short = max(1, round(METER_PIXELS * ratio))
        r.engine = "CYCLES"
        r.resolution_x, r.resolution_y = (METER_PIXELS, short) if wide else (short, METER_PIXELS)
        r.resolution_percentage = 100
        r.use_motion_blur = False
        r.film_transparent = False
        r.use_border = False
        r.use_compositing = False
        r.use_sequencer = False
        r.image_settings.file_format = "OPEN_EXR"  # scene-linear, before the view transform
        r.image_settings.color_mode = "RGBA"
        r.image_settings.color_depth = "32"
        r.filepath = path
        c = scene.cycles
        c.samples = METER_SAMPLES
        c.use_denoising = False
        if hasattr(c, "use_adaptive_sampling"):
            c.use_adaptive_sampling = False
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(path, check_existing=False)
        pixels = np.empty(len(image.pixels), np.float32)
        image.pixels.foreach_get(pixels)
        channels = max(1, int(image.channels))
        rgb = pixels.reshape(-1, channels)[:, :3] if channels >= 3 else np.repeat(pixels.reshape(-1, channels)[:, :1], 3, axis=1)
        if not np.isfinite(rgb).all():
            rgb = np.nan_to_num(rgb, nan=0.0, posinf=0.0, neginf=0.0)
        exposure = exposure_for(log_average(rgb))
    finally:
        if image is not None:
            bpy.data.images.remove(image)
        for (owner, name), value in kept.items():
            setattr(owner, name, value)
        try:
            os.remove(path)
        except OSError:
            pass
    scene.view_settings.exposure = exposure
    return exposure


class MeterExposure(bpy.types.Operator):
    """Set the view's exposure from a small render of the scene camera's view (its
    log-average luminance to middle grey), as a camera's meter would"""

    bl_idname = "scene.libwave_meter_exposure"
    bl_label = "Meter exposure (libwave)"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        exposure = meter(context)
        if exposure is None:
            self.report({"ERROR"}, "libwave: the scene has no camera to meter through")
            return {"CANCELLED"}
        self.report({"INFO"}, f"libwave: exposure {exposure:+.2f} stops")
        return {"FINISHED"}
