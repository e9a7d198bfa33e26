"""Stage 2 of the pipeline: a system with parameter values as a numeric tree (:mod:`.numeric`), written as URDF
(:mod:`.urdf`, yourdfpy) and MJCF (:mod:`.mjcf`, MuJoCo's MjSpec); the files of ``urdf/`` (:mod:`.files`)."""
