"""What a run keeps for the next (harness/kept.py): entries keyed by our installation, checked when read, and one
installation's entries per folder."""

import harness.kept as kept


def test_an_entry_is_read_back_damaged_is_none_and_another_installations_entries_are_removed(tmp_path, monkeypatch):
    monkeypatch.setattr(kept, "cache_dir", lambda: tmp_path / "derivations")
    monkeypatch.setattr(kept, "_FORGOTTEN", set())
    monkeypatch.setattr(kept, "installation", lambda: "a" * 64)
    first = kept.path("states", "pendulum", "200 states")
    assert first.parent == tmp_path / "states" and first.name.startswith("a" * 12 + "-pendulum-")
    assert kept.path("states", "pendulum", "100 states") != first
    kept.keep(first, {"q": [0.1, 1e-300]})
    assert kept.read_kept(first) == {"q": [0.1, 1e-300]}
    first.write_text(first.read_text().replace("0.1", "0.2"))   # damaged: the checksum no longer matches
    assert kept.read_kept(first) is None and kept.read_kept(tmp_path / "absent.json") is None

    monkeypatch.setattr(kept, "_FORGOTTEN", set())              # a new process of another installation
    monkeypatch.setattr(kept, "installation", lambda: "b" * 64)
    second = kept.path("states", "pendulum", "200 states")
    assert second != first
    kept.keep(second, [1, 2])
    assert not first.exists() and kept.read_kept(second) == [1, 2]
    other = kept.path("exports", "pendulum.mjcf", "tree")       # another folder: forgotten on its own first entry
    kept.keep(other, "text")
    assert sorted(p.name for p in (tmp_path / "states").iterdir()) == [second.name]
