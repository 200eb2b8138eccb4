"""Generated NumPy kernels (see eulersym.codegen). Importable without SymPy."""
