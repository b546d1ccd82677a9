"""libwave: coastal wave tracing and animated water meshes.

Two routes, with the same results bit for bit:

* the whole scene: ``Scene`` (or ``read_scene``/``default_scene``) → ``plan`` →
  ``animate`` (frames as NumPy arrays) or ``write_animation`` (files as ``wave run``);
* stage by stage (examples/pipeline.py): ``read_seafloor`` → ``extract_isobaths`` →
  ``trace_fronts`` → ``solve_wave_field``/``take_field_amplitudes`` →
  ``build_ray_strips`` → ``mesh_water``/``resample_ray_strips`` →
  ``plan_gonzato_motion`` → ``breaking_foam`` → ``plan_untangle`` → ``vertex_normals``
  → ``fresnel_weights`` → ``frame_glb``.

Every failure is a ``libwave.Error``; bad input is ``libwave.InputError`` (also a
``ValueError``) and a guard rail ``libwave.LimitError`` (an ``InputError``), each
naming the file, key or argument and the value.
"""
from ._libwave import *  # noqa: F401,F403  (the compiled module: every public name)
from ._libwave import Error, InputError, LimitError, __version__  # noqa: F401
