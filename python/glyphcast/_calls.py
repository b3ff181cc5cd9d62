"""A wrong input raised from the user's call.

A wrong array or option is found below the public function that took it: in the native
module, or in a helper some frames down (``show_sh`` reaches the array's check through
the view, its loader and the renderer's). Its traceback would run through each of those
frames, and the one line that matters, the message, comes after a screen of glyphcast's
own code. The public functions are wrapped so that a ValueError or TypeError (what a
wrong input raises; a failure of the device is a RuntimeError and keeps its whole
traceback) leaves them with the traceback cut at the wrapper: the user's line, one frame
of glyphcast, the message. ``GLYPHCAST_FULL_TRACEBACK=1`` keeps every frame, for work on
glyphcast itself.
"""
import functools
import os

INPUT_ERRORS = (ValueError, TypeError)


def at_the_call(function):
    """``function``, its input errors raised from its own frame."""

    @functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except INPUT_ERRORS as error:
            if os.environ.get("GLYPHCAST_FULL_TRACEBACK") == "1":
                raise
            raise error.with_traceback(None)  # a wrong input: see the message below

    # The one frame left is named as the function the user called ("in show_sh"), not
    # as this wrapper.
    names = {"co_name": function.__name__}
    if hasattr(call.__code__, "co_qualname"):  # Python 3.11
        names["co_qualname"] = function.__qualname__
    call.__code__ = call.__code__.replace(**names)
    return call
