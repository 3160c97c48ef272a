"""The dynamics: parameters, the closed-form flight, impact location, the jitted event loop and
:func:`~vibroimpact.dynamics.runs.simulate`.  Imports nothing of the layers above it."""
