"""Named options resolved in one place, with errors that list the valid names."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Generic, TypeVar

from ._errors import OptionError

__all__ = ["Registry"]

T = TypeVar("T")


class Registry(Generic[T]):
    """A small mapping from option names to implementations.

    Parameters
    ----------
    option : str
        The name of the option the registry resolves, used in error messages
        (for example ``"distance"``).

    Examples
    --------
    >>> modes = Registry("mode")
    >>> modes.add("fast", 1)
    >>> modes.get("fast")
    1
    >>> modes.get("slow")
    Traceback (most recent call last):
    ...
    ndlfd._errors.OptionError: unknown mode 'slow'; expected one of: 'fast'
    """

    def __init__(self, option: str) -> None:
        self.option = option
        self._items: dict[str, T] = {}

    def add(self, name: str, item: T) -> None:
        """Register ``item`` under ``name``."""
        if name in self._items:
            raise KeyError(f"{self.option} {name!r} is registered twice")
        self._items[name] = item

    def register(self, name: str) -> Callable[[T], T]:
        """Decorate a function or class to register it under ``name``."""

        def deco(item: T) -> T:
            self.add(name, item)
            return item

        return deco

    def get(self, name: str) -> T:
        """Return the item registered under ``name`` or raise :class:`OptionError`."""
        if not isinstance(name, str) or name not in self._items:
            choices = ", ".join(repr(k) for k in self._items)
            raise OptionError(
                f"unknown {self.option} {name!r}; expected one of: {choices}"
            )
        return self._items[name]

    def check(self, name: str) -> str:
        """Return ``name`` if it is registered, else raise :class:`OptionError`."""
        self.get(name)
        return name

    @property
    def names(self) -> tuple[str, ...]:
        """The registered names, in registration order."""
        return tuple(self._items)

    def __contains__(self, name: object) -> bool:
        return name in self._items

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)
