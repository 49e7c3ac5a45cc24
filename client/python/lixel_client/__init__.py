"""lixel's Python client: a channel to a lixel server and its Session stream (docs/service.md,
"Sessions"). Installed with the stubs the build generates (lixel.v1) and the coded-map decoder
(lixel_maps); see the README for the two commands."""

from lixel_client.session import Frame, Session, StreamError, connect, instance, mat4

__all__ = ["Frame", "Session", "StreamError", "connect", "instance", "mat4"]
