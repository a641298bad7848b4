"""Read-only attributes that the package's classes take from their native object or view."""

from __future__ import annotations

from typing import Any, Generic, Optional, TypeVar, overload

import numpy as _np

T = TypeVar("T")


class Native(Generic[T]):
    """A read-only attribute of the same name on the native object ``self._inner``."""

    def __init__(self, doc: str) -> None:
        self.__doc__ = doc
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @overload
    def __get__(self, obj: None, objtype: Optional[type] = None) -> "Native[T]": ...
    @overload
    def __get__(self, obj: object, objtype: Optional[type] = None) -> T: ...

    def __get__(self, obj: Any, objtype: Optional[type] = None) -> Any:
        if obj is None:
            return self
        return getattr(obj._inner, self.name)


class View(Native[_np.ndarray]):
    """A read-only numpy view of the engine's array of the same name (``self._view(name)``)."""

    def __get__(self, obj: Any, objtype: Optional[type] = None) -> Any:
        if obj is None:
            return self
        return obj._view(self.name)
