"""libwave: coastal wave tracing and animated water meshes.

Two routes, with the same results bit for bit:

* the whole scene: ``Scene`` (or ``read_scene``/``default_scene``) → ``plan`` →
  ``animate`` (frames as NumPy arrays), ``write_animation`` (files as ``wave run``) or
  ``write_files_form`` (one .glb per frame and index.json, resumable, as ``wave run --form files``);
* stage by stage (examples/pipeline.py): ``read_seafloor`` → ``extract_isobaths`` →
  ``trace_fronts`` → ``solve_wave_field``/``take_field_amplitudes`` →
  ``build_ray_strips`` → ``mesh_water``/``resample_ray_strips`` →
  ``plan_gonzato_motion`` → ``breaking_foam`` → ``plan_untangle`` → ``vertex_normals``
  → ``fresnel_weights`` → ``frame_glb`` (one frame) or ``animation_glb`` (frames as one
  morph or nodes .glb).

Every failure is a ``libwave.Error``; bad input is ``libwave.InputError`` (also a
``ValueError``; a wrong shape or length of an array argument too), an argument of the
wrong type or layout ``libwave.ArgumentTypeError`` (an ``InputError`` that is also a
``TypeError``: an array of strings, a float64 buffer where a float32 frame is written, and
every call whose arguments no signature takes: a camera of two numbers, a str for a number)
and a guard rail ``libwave.LimitError`` (an ``InputError``), each naming the file, key
or argument and the value.
"""
from ._libwave import *  # noqa: F401,F403  (the compiled module: every public name)
from ._libwave import ArgumentTypeError, Error, InputError, LimitError, __version__  # noqa: F401
