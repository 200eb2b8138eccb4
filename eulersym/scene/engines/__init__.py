"""Moved: the ways of getting a scene's motion are one family in :mod:`eulersym.numerics.methods` (a class each,
one registry, one driver: :func:`eulersym.numerics.methods.get`, :func:`~eulersym.numerics.methods.solve`).

This empty package stays only because ``pyproject.toml`` still lists ``eulersym.scene.engines`` among the packages
(a build fails on a listed package that is missing); it goes with that line, which becomes
``eulersym.numerics.methods``.
"""
