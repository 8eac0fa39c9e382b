"""The parsers' cache (tockbmc/model/grammars.py): built once, loaded after, never trusted blindly."""

from __future__ import annotations

from pathlib import Path

import lark
import pytest

from tockbmc.model import grammars

OPTIONS = {"start": ["rct", "assertions"], "propagate_positions": True, "maybe_placeholders": False}
TEXT = "stm S {\n  initial i\n  state s { }\n  transition t0 { from i to s }\n}\n"


def _built(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> lark.Lark:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    return grammars.build("robochart.lark", **OPTIONS)


def test_a_parser_is_built_once_then_loaded(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    first = _built(monkeypatch, tmp_path)
    [saved] = (tmp_path / "tockbmc").iterdir()
    assert saved.suffix == ".lark" and not list((tmp_path / "tockbmc").glob("*.tmp"))

    def no_build(*args: object, **kwargs: object) -> None:
        raise AssertionError("the grammar was built again")

    monkeypatch.setattr(grammars, "Lark", type("NoBuild", (), {"__new__": no_build, "load": lark.Lark.load}))
    second = grammars.build("robochart.lark", **OPTIONS)
    tree = second.parse(TEXT, start="rct")
    assert tree == first.parse(TEXT, start="rct")
    assert [t.meta.line for t in tree.iter_subtrees()] == [t.meta.line for t in first.parse(TEXT, start="rct").iter_subtrees()]


def test_a_damaged_cache_file_is_built_again(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    _built(monkeypatch, tmp_path)
    [saved] = (tmp_path / "tockbmc").iterdir()
    saved.write_bytes(saved.read_bytes()[:1000])
    parser = grammars.build("robochart.lark", **OPTIONS)
    assert parser.parse(TEXT, start="rct").data == "rct"
    assert saved.stat().st_size > 1000  # written whole again


def test_an_unwritable_cache_only_costs_time(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    assert grammars.build("robochart.lark", **OPTIONS).parse(TEXT, start="rct").data == "rct"


def test_a_cache_others_may_write_is_never_loaded(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """A cache file is a pickle: one in a directory others may write could run their code (a file
    planted in a mode-777 directory would run `os.system`)."""
    _built(monkeypatch, tmp_path)
    folder = tmp_path / "tockbmc"
    [saved] = folder.iterdir()
    saved.write_bytes(b"not a pickle anyone should load")
    folder.chmod(0o777)
    loaded: list[object] = []
    monkeypatch.setattr(lark.Lark, "load", classmethod(lambda cls, f: loaded.append(f)))
    assert grammars.build("robochart.lark", **OPTIONS).parse(TEXT, start="rct").data == "rct"
    assert not loaded and saved.read_bytes() == b"not a pickle anyone should load"  # neither read nor written


def test_a_relative_cache_home_is_ignored(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/dir")
    monkeypatch.setenv("HOME", str(tmp_path))
    assert grammars.cache_dir() == tmp_path / ".cache" / "tockbmc"
