"""geompm deletes and overwrites only what it made (issue 14, point 3 and 5).

Every refusal runs in a temporary folder full of user files (text, binary,
nested folders, a look-alike run folder) and must leave each of them
byte-identical, checked by SHA-256 of every file; it must exit with code 2
and say why.  The positive side is checked too: ``--overwrite`` on a folder
that ``geompm run`` made replaces it (the old run's files are gone, the new
run's marker is in place).
"""

import hashlib
import json
import os
from pathlib import Path

import pytest

from geompm.cli import main
from geompm.errors import CaseError
from geompm.files.ownership import MARKER, owned_kind, remove_file, remove_tree

from tests.support.cases import tiny_case

QUICK = ["--quiet", "--set", "time.end=0.002", "--set", "outputs=[]"]


def _hashes(root: Path) -> dict:
    return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(root.rglob("*")) if p.is_file() and not p.is_symlink()}


@pytest.fixture
def user_tree(tmp_path, monkeypatch):
    """tmp_path as the current folder, holding a case and a user's files; returns (root, case path, hashes)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "home" / "data").mkdir(parents=True)
    (tmp_path / "home" / "data" / "thesis.txt").write_text("four years of work\n")
    (tmp_path / "home" / "photo.bin").write_bytes(os.urandom(4096))
    (tmp_path / "notes.md").write_text("# notes\n")
    (tmp_path / "looks_like_a_run").mkdir()
    for name in ("case.json", "series.csv", "run.log"):
        (tmp_path / "looks_like_a_run" / name).write_text("mine\n")
    (tmp_path / "project" / "cases").mkdir(parents=True)
    case = tmp_path / "project" / "cases" / "tiny.json"
    case.write_text(json.dumps(tiny_case()))
    return tmp_path, case, _hashes(tmp_path)


def _refused(capsys, argv, words) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert words in err, err
    return err


@pytest.mark.parametrize("out,words", [
    (".", "is the current folder"),
    ("home", "was not made by geompm"),
    ("looks_like_a_run", "was not made by geompm"),
    ("project", "holds the folder of the case file"),
    ("project/cases", "is the folder of the case file"),
    ("..", "holds the current folder"),
    ("/", "never deletes it"),
])
def test_overwrite_refuses_folders_geompm_did_not_make(user_tree, capsys, out, words):
    root, case, before = user_tree
    _refused(capsys, ["run", str(case), "--out", out, "--overwrite", *QUICK], words)
    assert _hashes(root) == before


def test_overwrite_refuses_the_home_folder(user_tree, capsys, monkeypatch):
    """Even a folder geompm made is not deleted when it is the home folder."""
    root, case, _ = user_tree
    assert main(["run", str(case), "--out", "made", *QUICK]) == 0
    monkeypatch.setenv("HOME", str(root / "made"))
    before = _hashes(root)
    _refused(capsys, ["run", str(case), "--out", "made", "--overwrite", *QUICK], "your home folder")
    assert _hashes(root) == before


def test_overwrite_refuses_copied_linked_and_other_kinds(user_tree, capsys):
    """A copy of a run folder (marker for another path), a link to one, and a study folder are not runs
    geompm made there."""
    import shutil

    root, case, _ = user_tree
    assert main(["run", str(case), "--out", "made", *QUICK]) == 0
    shutil.copytree(root / "made", root / "copy")
    (root / "link").symlink_to(root / "made")
    (root / "study").mkdir()
    (root / "study" / MARKER).write_text(json.dumps({"kind": "study", "path": str((root / "study").resolve())}))
    before = _hashes(root)
    _refused(capsys, ["run", str(case), "--out", "copy", "--overwrite", *QUICK], "copied or moved")
    _refused(capsys, ["run", str(case), "--out", "link", "--overwrite", *QUICK], "symbolic link")
    _refused(capsys, ["run", str(case), "--out", "study", "--overwrite", *QUICK], "not a run folder")
    assert _hashes(root) == before


@pytest.mark.parametrize("name", [".", "..", ".hidden", "../up", "a/b", ""])
def test_run_names_that_are_not_plain_folder_names_are_refused(user_tree, capsys, name):
    root, case, before = user_tree
    case.write_text(json.dumps(tiny_case(name=name)))
    before = _hashes(root)
    err = _refused(capsys, ["run", str(case), *QUICK], "name:")
    assert "'.'" in err or "string" in err or "pattern" in err or "at least" in err
    assert _hashes(root) == before and not (root / "runs").exists()


def test_overwrite_replaces_a_run_folder_geompm_made(user_tree):
    """The positive side: the old run's files go (a stale file too), the new run has its marker."""
    root, case, _ = user_tree
    assert main(["run", str(case), "--out", "made", *QUICK]) == 0
    stale = root / "made" / "old_output.vtu"
    stale.write_text("from the first run\n")
    first = json.loads((root / "made" / MARKER).read_text())["created"]
    assert main(["run", str(case), "--out", "made", "--overwrite", *QUICK]) == 0
    assert not stale.exists()
    assert owned_kind(root / "made") == "run"
    assert (root / "made" / "status.json").is_file()
    assert json.loads((root / "made" / MARKER).read_text())["created"] >= first


def test_existing_run_folder_without_overwrite_is_refused(user_tree, capsys):
    root, case, _ = user_tree
    assert main(["run", str(case), "--out", "made", *QUICK]) == 0
    before = _hashes(root)
    _refused(capsys, ["run", str(case), "--out", "made", *QUICK], "already exists")
    assert _hashes(root) == before


def test_study_and_calibrate_refuse_user_folders(user_tree, capsys):
    """`geompm study --overwrite` and `--resume`, and `geompm calibrate`, on a folder of the user's."""
    root, case, before = user_tree
    _refused(capsys, ["study", str(case), "--vary", "grid.cell_size=0.1,0.05", "--out", "home", "--overwrite",
                      "--quiet"], "was not made by geompm")
    _refused(capsys, ["study", str(case), "--vary", "grid.cell_size=0.1,0.05", "--out", "home", "--resume",
                      "--quiet"], "not a geompm study folder")
    _refused(capsys, ["study", str(case), "--vary", "grid.cell_size=0.1,0.05", "--out", ".", "--overwrite",
                      "--quiet"], "is the current folder")
    assert _hashes(root) == before


def test_calibrate_refuses_a_user_folder(user_tree, capsys):
    from tests.support.cases import CASES

    root, _, before = user_tree
    seed = CASES / "seed"
    _refused(capsys, ["calibrate", str(seed / "dp_h0.02.json"), "--fluid", str(seed / "cross.json"),
                      "--out", "home", "--quiet"], "not a geompm calibration folder")
    assert _hashes(root) == before


def test_schema_and_plot_do_not_overwrite_user_files(user_tree, capsys):
    root, case, _ = user_tree
    assert main(["run", str(case), "--out", "made", *QUICK]) == 0
    (root / "pngs").mkdir()
    (root / "pngs" / "series.png").write_bytes(b"my own figure")
    before = _hashes(root)
    _refused(capsys, ["schema", "-o", "notes.md"], "not a geompm case schema")
    _refused(capsys, ["plot", "made", "-o", "pngs"], "did not make it")
    assert _hashes(root) == before
    assert main(["schema", "-o", "fresh.schema.json"]) == 0
    assert main(["schema", "-o", "fresh.schema.json"]) == 0  # its own schema file may be regenerated
    assert json.loads((root / "fresh.schema.json").read_text())["title"] == "Case"


def test_the_guarded_helpers_refuse_user_paths(user_tree):
    """remove_tree and remove_file are the only deletes in geompm (see test_one_delete_helper)."""
    root, _, before = user_tree
    for call in (lambda: remove_tree(root / "home", "run"), lambda: remove_file(root / "notes.md"),
                 lambda: remove_file(root / "looks_like_a_run" / "series.csv")):
        with pytest.raises(CaseError):
            call()
    assert _hashes(root) == before


def test_one_delete_helper():
    """No module of geompm deletes a file except geompm/files/ownership.py (an AST scan for .unlink(), .rmdir(),
    shutil.rmtree(), os.remove() and os.removedirs() calls)."""
    import ast

    pkg = Path(__file__).resolve().parents[2] / "geompm"
    offenders = []
    for src in pkg.rglob("*.py"):
        if src.relative_to(pkg).as_posix() == "files/ownership.py":
            continue
        for node in ast.walk(ast.parse(src.read_text())):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
                continue
            attr, owner = node.func.attr, node.func.value
            if attr in ("unlink", "rmtree", "rmdir", "removedirs") or (
                    attr == "remove" and isinstance(owner, ast.Name) and owner.id == "os"):
                offenders.append(f"{src.relative_to(pkg)}:{node.lineno} .{attr}()")
    assert not offenders, offenders


def test_resume_of_a_moved_run_folder_takes_it_over(user_tree):
    """A run folder moved elsewhere and resumed there is marked for its new path (it rotates checkpoints
    there); a copied folder that is not resumed stays someone else's (see the copy test above)."""
    import shutil

    root, case, _ = user_tree
    assert main(["run", str(case), "--out", "made", "--quiet", "--set", "outputs=[]"]) == 0
    shutil.move(root / "made", root / "moved")
    assert owned_kind(root / "moved") is None
    assert main(["run", str(case), "--set", "outputs=[]", "--set", "time.end=0.08", "--resume", "moved",
                 "--quiet"]) == 0
    assert owned_kind(root / "moved") == "run"
    assert json.loads((root / "moved" / MARKER).read_text())["adopted"] is True


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_files_get_the_users_umask(tmp_path, monkeypatch, umask, mode):
    """Every file a run writes (case.json, status.json, series.csv, VTU, PVD, HDF5, checkpoints, the folder
    marker) has the mode a new file gets under the user's umask (0o666 less the umask), still written
    atomically: mkstemp's private 0o600 made the results unreadable to colleagues under umask 022."""
    monkeypatch.chdir(tmp_path)
    case = tmp_path / "tiny.json"
    case.write_text(json.dumps(tiny_case(outputs=[{"writer": "vtu", "interval": 0.01},
                                                  {"writer": "hdf5", "interval": 0.01}],
                                         run={"checkpoint_interval": 0.01})))
    old = os.umask(umask)
    try:
        assert main(["run", str(case), "--quiet", "--out", "out"]) == 0
    finally:
        os.umask(old)
    files = [p for p in (tmp_path / "out").rglob("*") if p.is_file()]
    names = {p.name for p in files}
    assert {"case.json", "status.json", "series.csv", "particles.pvd", "results.h5"} <= names
    assert any(p.suffix == ".vtu" for p in files) and any("checkpoints" in p.parts for p in files)
    modes = {str(p.relative_to(tmp_path)): oct(p.stat().st_mode & 0o777) for p in files}
    assert all(m == oct(mode) for m in modes.values()), modes
