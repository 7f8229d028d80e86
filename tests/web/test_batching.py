"""Dynamic batching of the explorer's predictions (sandlight.web.batching, spectra.*_many)."""

import asyncio

import httpx
import numpy as np
import pytest

from sandlight.sample import SandSample
from sandlight.web import create_app, spectra
from sandlight.web.batching import Batcher


def test_requests_waiting_together_are_answered_by_one_call_in_their_order():
    calls = []

    def answer_many(items):
        calls.append(list(items))
        return [2 * x for x in items]

    async def main():
        batcher = Batcher(answer_many)
        return await asyncio.gather(*(batcher(i) for i in range(7)))

    assert asyncio.run(main()) == [0, 2, 4, 6, 8, 10, 12]
    assert calls == [list(range(7))]


def test_a_lone_request_is_answered_alone_and_later_ones_form_a_new_batch():
    calls = []

    def answer_many(items):
        calls.append(list(items))
        return list(items)

    async def main():
        batcher = Batcher(answer_many)
        first = await batcher("a")
        rest = await asyncio.gather(batcher("b"), batcher("c"))
        return first, rest

    assert asyncio.run(main()) == ("a", ["b", "c"])
    assert calls == [["a"], ["b", "c"]]


def test_only_the_request_whose_item_fails_sees_the_exception():
    def answer_many(items):
        if "bad" in items:
            raise ValueError("bad item")
        return [x.upper() for x in items]

    async def main():
        batcher = Batcher(answer_many)
        return await asyncio.gather(batcher("x"), batcher("bad"), batcher("y"), return_exceptions=True)

    x, bad, y = asyncio.run(main())
    assert (x, y) == ("X", "Y")
    assert isinstance(bad, ValueError) and "bad item" in str(bad)


def test_a_cancelled_request_is_not_answered_and_does_not_stop_the_others():
    seen = []

    def answer_many(items):
        seen.extend(items)
        return list(items)

    async def main():
        batcher = Batcher(answer_many)
        gone = asyncio.ensure_future(batcher("gone"))
        kept = asyncio.ensure_future(batcher("kept"))
        await asyncio.sleep(0)  # both are waiting
        gone.cancel()
        return await kept

    assert asyncio.run(main()) == "kept"
    assert seen == ["kept"]


def test_a_full_batch_is_answered_without_waiting_for_more():
    calls = []

    def answer_many(items):
        calls.append(len(items))
        return list(items)

    async def main():
        batcher = Batcher(answer_many, max_batch=4)
        return await asyncio.gather(*(batcher(i) for i in range(4)))

    assert asyncio.run(main()) == [0, 1, 2, 3]
    assert calls == [4]


def _samples():
    red = SandSample.preset("red-dune")
    inside = [red.replace(iron_oxide=x) for x in (0.011, 0.023, 0.037)]
    outside = red.replace(depth_mm=5.0)  # no shipped model is trained on a finite layer
    return [inside[0], outside, inside[1], inside[0], inside[2]]


def test_many_predictions_equal_each_prediction_alone_covered_or_not():
    samples = _samples()
    together = spectra.predict_many(samples)
    values, used = spectra.bank().predict([s for s in samples if s.depth_mm == np.inf], return_models=True)
    covered = [p for p in together if p.covered]
    assert [p.model for p in covered] == [str(u) for u in used]
    np.testing.assert_allclose(np.stack([p.reflectance for p in covered]), values, rtol=0, atol=1e-12)
    assert not together[1].covered and "depth_mm" in together[1].description
    assert together[0] is together[3]  # one answer kept per sample


def test_concurrent_http_requests_get_the_answers_of_requests_made_one_by_one():
    samples = _samples()
    bodies = [{"sample": s.to_dict(), "compare": "yellow-dune"} for s in samples]

    async def main():
        app = create_app()
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1") as http:
            spectra_ = await asyncio.gather(*(http.post("/api/spectrum", json={"sample": b["sample"]}) for b in bodies))
            colours = await asyncio.gather(*(http.post("/api/colour", json=b) for b in bodies))
        return [r.json() for r in spectra_], [r.json() for r in colours]

    spectrum_bodies, colour_bodies = asyncio.run(main())
    for sample, spectrum_body, colour_body in zip(samples, spectrum_bodies, colour_bodies):
        assert spectrum_body == spectra.spectrum_answer(sample)
        alone = spectra.colour_answer(sample, SandSample.preset("yellow-dune"))
        assert colour_body.keys() == alone.keys()
        assert colour_body["a"] == alone["a"]
        if alone["delta_e2000"] is None:
            assert colour_body["delta_e2000"] is None
        else:
            assert colour_body["delta_e2000"] == pytest.approx(alone["delta_e2000"], abs=1e-9)
