"""Jupyter server extension: send kernel websocket messages without Nagle's delay (``TCP_NODELAY``).

Why: a widget round trip (a drag message in, the redrawn curve out) makes the kernel publish several
small messages in a row (``status: busy``, the widget update, ``status: idle``). jupyter_server writes each
as its own websocket frame and does not set ``TCP_NODELAY`` on the kernel websocket, so with Nagle's
algorithm the second frame waits until the browser acknowledges the first -- and browsers delay that
acknowledgement (Linux: up to 40 ms). Every drag answer then arrives ~40 ms late although the kernel
needs about a millisecond (``benchmarks/bench_drag.py`` measures both ways side by side). Tornado
documents the cure (``WebSocketHandler.set_nodelay``); this extension applies it to the kernel websockets.

Installing splinecraft enables it for every Jupyter server of the environment: the wheel puts
``jupyter-config/jupyter_server_config.d/splinecraft.json`` into ``etc/jupyter/jupyter_server_config.d``
(``pyproject.toml``, shared-data). Turn it off with ``jupyter server extension disable splinecraft.jupyter_nodelay``,
or for one server with ``jupyter lab --ServerApp.jpserver_extensions='{"splinecraft.jupyter_nodelay": false}'``.
It is not a widget and imports nothing from splinecraft; it changes nothing but ``TCP_NODELAY``.
"""
from __future__ import annotations

__all__ = ["enable_nodelay"]


def enable_nodelay(handler_class=None) -> bool:
    """Patch the kernel websocket handler so every connection sets ``TCP_NODELAY``; True if newly patched."""
    if handler_class is None:
        from jupyter_server.services.kernels.websocket import KernelWebsocketHandler as handler_class
    if getattr(handler_class, "_splinecraft_nodelay", False):
        return False
    original_open = handler_class.open

    async def open(self, *args, **kwargs):  # noqa: A001 - the tornado method name
        self.set_nodelay(True)
        return await original_open(self, *args, **kwargs)

    handler_class.open = open
    handler_class._splinecraft_nodelay = True
    return True


def _jupyter_server_extension_points():
    return [{"module": "splinecraft.jupyter_nodelay"}]


def _load_jupyter_server_extension(serverapp):
    if enable_nodelay():
        serverapp.log.info("splinecraft: TCP_NODELAY on kernel websockets (no Nagle delay for widget round trips)")
