"""Generated NumPy kernels, importable without SymPy: ``eulersym.generated.<name>``.

Written by ``eulersym generate`` from the catalogue in :mod:`eulersym.codegen.catalogue` (do not edit the modules
by hand; ``eulersym generate --check`` fails when one is stale, missing or extra). Each module's docstring and
header state its functions, their argument order and the derivation it came from.
"""
