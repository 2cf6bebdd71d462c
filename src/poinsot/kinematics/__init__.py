"""poinsot.kinematics (see the area's page in docs/)."""

# Assembled from the area's modules. While they are written in parallel a module
# that does not exist yet is skipped; the lead replaces this with explicit
# imports once the area lands.
from importlib import import_module as _import_module

__all__: list[str] = []
for _name in ['rates', 'attitude_history', 'propagation', 'fields', 'screw', 'point']:
    try:
        _mod = _import_module(f".{_name}", __name__)
    except ModuleNotFoundError as _exc:
        if _exc.name == f"{__name__}.{_name}":
            continue
        raise
    for _public in getattr(_mod, "__all__", []):
        globals()[_public] = getattr(_mod, _public)
        __all__.append(_public)
