"""The command line: help, version, exit codes, one clear error line, data on stdout."""

from __future__ import annotations

import io
import logging
import subprocess
import sys
from pathlib import Path

import pytest

from belvedere import __version__
from belvedere.cli import main
from tests.conftest import DATA, EXAMPLES

MBOT_WRAPPER = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"


def test_help_and_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    assert "xacro" in capsys.readouterr().out
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"belvedere {__version__}"


def test_usage_error_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["no-such-verb"]) == 2
    assert main([]) == 2
    assert main(["xacro"]) == 2
    assert "FILE" in capsys.readouterr().err


def test_main_leaves_logging_as_it_found_it(
    capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    """main() called in-process (as tests and scripts do) must not leave a handler on a
    stream that is gone once it returns, nor keep records from the application's logging."""
    for _ in range(2):
        stderr = io.StringIO()  # like a test's capture: replaced, then closed
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(sys, "stderr", stderr)
            assert main(["check", str(MBOT_WRAPPER)]) == 0
        stderr.close()
    logging.getLogger("belvedere.graph").warning("after main() returned")
    assert "Logging error" not in capsys.readouterr().err
    assert [r.getMessage() for r in caplog.records] == ["after main() returned"]


def test_python_dash_m_works() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "belvedere", "--version"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0
    assert proc.stdout.startswith("belvedere ")


def test_xacro_writes_urdf_to_stdout_and_warnings_to_stderr(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["xacro", str(MBOT_WRAPPER)]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith('<?xml version="1.0" ?>')
    assert captured.out.count("<link ") == 6
    assert captured.err.startswith("note: 8 legacy macro calls without the 'xacro:' prefix in ")


def test_quiet_hides_warnings(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["-q", "xacro", str(MBOT_WRAPPER)]) == 0
    assert capsys.readouterr().err == ""


def test_error_is_one_message_and_exit_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.xacro"
    bad.write_text("<robot>\n  <link>\n</robot>\n")
    assert main(["xacro", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:3:3: error: malformed XML: mismatched tag")
    assert "Traceback" not in err


def test_debug_shows_traceback(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.xacro"
    bad.write_text("<robot>")
    assert main(["--debug", "xacro", str(bad)]) == 1
    assert "Traceback" in capsys.readouterr().err


def test_output_file_and_mappings(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(DATA / "xacro" / "modern")
    out = tmp_path / "new" / "dir" / "args.urdf"
    assert main(["xacro", "args.xacro", "a:=0", "-o", str(out)]) == 0
    text = out.read_text()
    assert 'a="0"' in text
    assert "<yes/>" not in text


def test_deps_lists_included_files(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(DATA / "xacro" / "modern")
    assert main(["xacro", "--deps", "include_main.xacro"]) == 0
    deps = capsys.readouterr().out.split()
    assert deps[0] == "./inc/part.xacro" or deps[0].endswith("inc/part.xacro")
    assert any(d.endswith("inc/deeper.xacro") for d in deps)


def test_inorder_is_accepted_with_a_notice(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(DATA / "xacro" / "modern")
    assert main(["xacro", "--inorder", "args.xacro"]) == 0
    assert "in-order processing became default" in capsys.readouterr().err


def test_check_order_reports_incompatible_documents(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(DATA / "xacro" / "legacy")
    assert main(["xacro", "--check-order", "two_pass.xacro"]) == 1
    assert "incompatible to in-order processing" in capsys.readouterr().err
    assert main(["xacro", "--check-order", "unprefixed_calls.xacro"]) == 0


def test_unexpected_positional_arguments(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["xacro", str(MBOT_WRAPPER), "stray"]) == 1
    assert "name:=value" in capsys.readouterr().err


def test_package_path_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot = tmp_path / "elsewhere" / "robot.xacro"
    robot.parent.mkdir()
    robot.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find mbot_description)/urdf/xacro/gazebo/'
        'mbot_base_gazebo_modern.xacro"/><xacro:mbot_base_gazebo/></robot>'
    )
    assert main(["xacro", str(robot)]) == 1
    assert "package 'mbot_description' not found" in capsys.readouterr().err
    assert main(["--package-path", str(EXAMPLES), "xacro", str(robot)]) == 0
    assert capsys.readouterr().out.count("<link ") == 6


def test_launch_file_spelling_runs_the_same_code() -> None:
    from belvedere.description.xacro import parse_xacro_argv, process_file, run_command

    cmd = parse_xacro_argv(["--inorder", str(MBOT_WRAPPER), "unused:=1"])
    assert cmd.mappings == {"unused": "1"}
    assert run_command(cmd).text == process_file(MBOT_WRAPPER, mappings={"unused": "1"})


@pytest.mark.parametrize(
    "program",
    ["/opt/ros/melodic/share/xacro/xacro", "xacro", "/opt/ros/kinetic/lib/xacro/xacro.py"],
)
def test_launch_command_strings(program: str) -> None:
    from belvedere.description.xacro import parse_xacro_command, run_command

    cmd = parse_xacro_command(f"{program} --inorder '{MBOT_WRAPPER}' use_gui:=true")
    assert cmd.input == str(MBOT_WRAPPER)
    assert cmd.mappings == {"use_gui": "true"}
    result = run_command(cmd)
    assert result.text is not None
    assert result.text.count("<link ") == 6


def test_not_a_xacro_command() -> None:
    from belvedere.description.xacro import XacroError, parse_xacro_command

    with pytest.raises(XacroError, match="not a xacro command"):
        parse_xacro_command("cat robot.urdf")


def test_unwritable_output_is_a_clear_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["-q", "xacro", str(MBOT_WRAPPER), "-o", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"error: cannot write {tmp_path}")
    assert "Traceback" not in err


def test_failed_expansion_leaves_existing_output_untouched(tmp_path: Path) -> None:
    out = tmp_path / "robot.urdf"
    out.write_text("previous")
    bad = tmp_path / "bad.xacro"
    bad.write_text("<robot><unclosed></robot>")
    assert main(["xacro", str(bad), "-o", str(out)]) == 1
    assert out.read_text() == "previous"


def test_output_replacing_a_file_keeps_its_permissions(tmp_path: Path) -> None:
    out = tmp_path / "robot.urdf"
    out.write_text("previous")
    out.chmod(0o644)
    assert main(["-q", "xacro", str(MBOT_WRAPPER), "-o", str(out)]) == 0
    assert out.read_text().startswith("<?xml")
    assert out.stat().st_mode & 0o777 == 0o644
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.urdf"]


def _big_urdf(tmp_path: Path) -> Path:
    links = "".join(f'  <link name="link_{i}"/>\n' for i in range(4000))
    big = tmp_path / "big.urdf"
    big.write_text(f'<robot name="big">\n{links}</robot>\n')
    return big


def test_output_on_a_full_disk_keeps_the_old_file(
    tmp_path: Path, full_disk: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = full_disk / "robot.urdf"
    out.write_text("previous")
    assert main(["xacro", str(_big_urdf(tmp_path)), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err == (f"error: cannot write {out}: No space left on device; {out} is unchanged\n")
    assert out.read_text() == "previous"
    assert sorted(p.name for p in full_disk.iterdir()) == ["robot.urdf"]


def test_a_thread_that_never_ends_does_not_hang_the_command() -> None:
    """Once the verb is done, a thread still running (a library's, a bug's) does not keep
    the command alive: after SHUTDOWN_S it prints every thread's stack and exits 1."""
    code = (
        "import sys, threading, time\n"
        "import belvedere.cli as cli\n"
        "cli.SHUTDOWN_S = 0.5\n"
        "threading.Thread(target=time.sleep, args=(600,), name='stuck').start()\n"
        "sys.argv = ['belvedere', '--version']\n"
        "cli.console()\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 1
    assert "Timeout (0:00:00.500000)!" in done.stderr
    assert "most recent call first" in done.stderr
