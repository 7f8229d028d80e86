"""Dynamic batching: concurrent requests answered by one vectorised call.

The bank of predictors and the colour conversions cost about the same for one sample as for a
few hundred (numpy's per-call overhead dominates), so when many clients ask at once the server
answers all requests that are waiting with one call instead of one call each, the "dynamic
batching" of model servers (e.g. NVIDIA Triton's dynamic batcher). A request joins the pending
batch; the batch is answered once an event-loop iteration has passed without a new request
joining (or it holds ``max_batch`` requests), so a lone request waits only a few loop iterations
(microseconds) and a burst is answered together.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Sequence
from typing import Any

__all__ = ["Batcher"]


class Batcher:
    """Answers ``await batcher(item)`` with ``answer_many([...items waiting...])``.

    Parameters
    ----------
    answer_many : callable
        Sequence of items → list of answers in the same order; runs on the event loop, so it
        must be quick (milliseconds).
    max_batch : int
        A batch this large is answered without waiting for more.

    Notes
    -----
    If ``answer_many`` raises for a batch, each item is answered alone, so only the requests
    whose own item fails see the exception. A request whose client has gone (its task
    cancelled) is skipped.
    """

    def __init__(self, answer_many: Callable[[Sequence[Any]], list[Any]], max_batch: int = 256) -> None:
        self._answer_many = answer_many
        self.max_batch = max_batch
        self._pending: list[tuple[Any, asyncio.Future]] = []

    async def __call__(self, item: Any) -> Any:
        loop = asyncio.get_running_loop()
        future = loop.create_future()
        self._pending.append((item, future))
        if len(self._pending) == 1:
            loop.call_soon(self._answer_when_quiet, 0)
        return await future

    def _answer_when_quiet(self, seen: int) -> None:
        waiting = len(self._pending)
        if seen < waiting < self.max_batch:  # still growing: give the others one more iteration
            asyncio.get_running_loop().call_soon(self._answer_when_quiet, waiting)
            return
        batch, self._pending = self._pending, []
        live = [(item, future) for item, future in batch if not future.done()]
        if not live:
            return
        try:
            answers = self._answer_many([item for item, _ in live])
        except Exception:
            for item, future in live:
                self._answer_one(item, future)
            return
        for (_, future), answer in zip(live, answers):
            if not future.done():
                future.set_result(answer)

    def _answer_one(self, item: Any, future: asyncio.Future) -> None:
        try:
            answer = self._answer_many([item])[0]
        except Exception as exc:
            future.set_exception(exc)
        else:
            future.set_result(answer)
