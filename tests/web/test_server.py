"""``sandlight serve``: loopback by default, another host only with --allow-remote and a warning."""

import pytest
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.errors import ParameterError
from sandlight.web import server


@pytest.mark.parametrize("host", ["127.0.0.1", "127.1.2.3", "::1", "[::1]", "localhost"])
def test_loopback_hosts_are_accepted(host):
    assert server.check_host(host, allow_remote=False) == host


@pytest.mark.parametrize("host", ["0.0.0.0", "192.168.1.5", "example.org", "::"])
def test_other_hosts_need_allow_remote(host):
    with pytest.raises(ParameterError, match="unless --allow-remote"):
        server.check_host(host, allow_remote=False)
    assert server.check_host(host, allow_remote=True) == host


class _Recorded:
    """A stand-in for uvicorn.Server that records its configuration instead of serving."""

    configs = []

    def __init__(self, config):
        self.configs.append(config)

    def run(self):
        pass


@pytest.fixture
def no_serving(monkeypatch):
    import uvicorn

    _Recorded.configs.clear()
    monkeypatch.setattr(uvicorn, "Server", _Recorded)
    return _Recorded.configs


def test_serve_binds_loopback_by_default_without_warning(no_serving):
    warned, said = [], []
    server.serve(open_browser=False, warn=warned.append, say=said.append)
    (config,) = no_serving
    assert config.host == "127.0.0.1" and config.port == server.DEFAULT_PORT
    assert not warned and said == ["sandlight explorer at http://127.0.0.1:8765/ (Ctrl-C stops it)"]


def test_serve_on_another_host_warns(no_serving):
    warned = []
    server.serve("0.0.0.0", 9000, allow_remote=True, open_browser=False, warn=warned.append, say=lambda s: None)
    assert no_serving[0].host == "0.0.0.0" and no_serving[0].port == 9000
    assert len(warned) == 1 and "reachable from other machines" in warned[0] and "no authentication" in warned[0]


def test_the_serve_command_passes_its_options(no_serving):
    res = CliRunner().invoke(app, ["serve", "--port", "9123", "--no-open"])
    assert res.exit_code == 0, res.output
    assert no_serving[0].port == 9123 and "http://127.0.0.1:9123/" in res.output
    res = CliRunner().invoke(app, ["serve", "--port", "70000", "--no-open"])
    assert res.exit_code == 2 and "--port = 70000 is not allowed" in res.output
