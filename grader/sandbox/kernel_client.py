"""The client the grader drives a sandboxed kernel with: jupyter_client's asynchronous one, ready as soon as the kernel is."""

from __future__ import annotations

import time
from queue import Empty

from jupyter_client.asynchronous import AsyncKernelClient

__all__ = ["SandboxedKernelClient"]

# How long one kernel_info request waits for its reply, and then for its "idle" on IOPub, before asking again.
_READY_ATTEMPT = 1.0


class SandboxedKernelClient(AsyncKernelClient):
    """jupyter_client's asynchronous client, ready as soon as the kernel is.

    jupyter_client's ``wait_for_ready`` ends by draining IOPub until it stays
    silent for 0.2 s, and checks that IOPub is connected with another 0.2 s
    wait: at least 0.2 s of idling per kernel start. Here the kernel is ready
    when it has answered a ``kernel_info`` request on the shell channel *and*
    reported ``idle`` for that same request on IOPub, which proves the IOPub
    subscription is live. Both are awaited as messages, not timeouts. Messages
    of other requests left in the channels do no harm: nbclient reads only the
    replies and outputs of the cell it runs (it matches the parent ``msg_id``).
    """

    async def wait_for_ready(self, timeout: float | None = None) -> None:
        deadline = time.monotonic() + (float("inf") if timeout is None else timeout)
        while True:
            msg_id = self.kernel_info()
            reply = await self._message_of(self.shell_channel, msg_id, lambda m: m["msg_type"] == "kernel_info_reply", deadline)
            if reply is not None:
                idle = await self._message_of(
                    self.iopub_channel, msg_id, lambda m: m["msg_type"] == "status" and m["content"].get("execution_state") == "idle", deadline
                )
                if idle is not None:
                    self._handle_kernel_info_reply(reply)
                    return
            if not await self._async_is_alive():
                raise RuntimeError("Kernel died before replying to kernel_info")
            if time.monotonic() > deadline:
                raise RuntimeError(f"Kernel didn't respond in {timeout:.0f} seconds")


    @staticmethod
    async def _message_of(channel, msg_id: str, wanted, deadline: float) -> dict | None:
        """The first message on ``channel`` answering ``msg_id`` that ``wanted`` accepts, within one attempt; None if none came."""
        until = min(deadline, time.monotonic() + _READY_ATTEMPT)
        while (left := until - time.monotonic()) > 0:
            try:
                msg = await channel.get_msg(timeout=left)
            except Empty:
                return None
            if msg.get("parent_header", {}).get("msg_id") == msg_id and wanted(msg):
                return msg
        return None
