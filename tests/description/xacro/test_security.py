"""The sandbox: expressions reach nothing but what xacro documents, every piece of work is
bounded, and parsing loads nothing external. Each refusal names the file, line and column."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from belvedere.description.xacro import XacroError, process_file, process_string
from belvedere.errors import ParseError

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def expand(body: str) -> str:
    return process_string(f"<robot {NS}>{body}</robot>")


def refused(tmp_path: Path, body: str) -> str:
    """The error text for a document whose second line is ``body``."""
    path = tmp_path / "evil.xacro"
    path.write_text(f'<robot name="r" {NS}>\n{body}\n</robot>\n', encoding="utf-8")
    with pytest.raises(XacroError) as info:
        process_file(path)
    return str(info.value).replace(str(path), "evil.xacro")


# --- reaching Python's object model ------------------------------------------------------------


def test_the_reported_escape_through_python_vars_is_refused_at_its_column(tmp_path: Path) -> None:
    # python.vars(type)['_'+'_subclasses_'+'_'] walked to subprocess.Popen through a dunder
    # name built by concatenation, which no check on names can see.
    text = refused(
        tmp_path,
        """  <xacro:property name="b" value="${python.vars(type)['_'+'_subclasses_'+'_']}"/>"""
        """\n  <link name="${b}"/>""",
    )
    # the column of '.vars' in the definition is reported, then where it was used
    assert text.startswith("evil.xacro:2:43: error: 'vars' is not available in expressions")
    assert "in property 'b', used at evil.xacro:3:3" in text


@pytest.mark.parametrize(
    ("expr", "message", "at"),
    [
        ("python.type(1)", "'type' is not available", ".type"),
        ("python.getattr", "'getattr' is not available", ".getattr"),
        ("vars(str)", "name 'vars' is not defined", "vars"),
        ("__import__('os')", "the name '__import__' is not allowed", "__import__"),
        ("().__class__", "the attribute '__class__' is not allowed", ".__class__"),
        ("(lambda: 1).__globals__", "the attribute '__globals__' is not allowed", ".__g"),
        ("[c for c in ().__class__.__mro__]", "the attribute '__mro__' is not allowed", ".__m"),
        ("str.mro()", "attribute 'mro' of a type value is not available", ".mro"),
        ("python.str.join(',', 'ab')", "attribute 'join' of a type value", ".join"),
        ("(x for x in [1]).gi_frame", "attribute 'gi_frame' of a generator value", ".gi_"),
        ("'a'.upper.__self__", "the attribute '__self__' is not allowed", ".__self__"),
        ("xacro.load_yaml.func", "attribute 'func' of a _Exposed value", ".func"),
        ("(1).real.imag.__class__", "the attribute '__class__' is not allowed", ".__class__"),
        ("math._ignored", "the attribute '_ignored' is not allowed", "._ignored"),
        ("[1].append(2)", "attribute 'append' of a list value", ".append"),
    ],
)
def test_private_and_unlisted_attributes_are_refused(
    tmp_path: Path, expr: str, message: str, at: str
) -> None:
    line = f'  <link name="${{{expr}}}"/>'
    text = refused(tmp_path, line)
    assert message in text
    # the column of the construct itself (of the expression's '${' for a raised error)
    col = line.index("${") + 1 if message.startswith("name ") else line.index(at) + 1
    assert text.startswith(f"evil.xacro:2:{col}: error: "), text


@pytest.mark.parametrize(
    ("fmt", "call", "message"),
    [
        ("{0.__class__}", "fmt.format(1)", "format field '{0.__class__}' is not allowed"),
        ("{0._Scope__x}", "fmt.format(xacro)", "format field '{0._Scope__x}' is not allowed"),
        ("{0[0]}", "fmt.format('ab')", "format field '{0[0]}' is not allowed"),
        ("{a.real}", "fmt.format_map(python.dict(a=1))", "format field '{a.real}' is not allowed"),
        ("{:99999999}", "fmt.format(1)", "a format width of 99999999 is too large"),
        ("%*d", "fmt % (99999999, 1)", "'*' widths in %-formatting are not allowed"),
        ("%.99999999f", "fmt % 1.0", "a format width of 99999999 is too large"),
        ("{x:>{w}}", "fmt.format(x=1, w=99999999)", "nested"),
    ],
)
def test_formatting_cannot_reach_attributes_or_build_huge_strings(
    tmp_path: Path, fmt: str, call: str, message: str
) -> None:
    # (a ${} cannot hold '}': the format string comes from a property, as in real files)
    body = f'  <xacro:property name="fmt" value="{fmt}"/>\n  <link name="${{{call}}}"/>'
    text = refused(tmp_path, body)
    assert text.startswith("evil.xacro:3:"), text
    if message != "nested":
        assert message in text


def test_fstrings_are_interpreted_too(tmp_path: Path) -> None:
    body = '  <xacro:property name="f" value="f\'{x.__class__}\'"/>\n  <a v="${f}"/>'
    assert 'v="f' in expand(body.replace("\n", ""))  # a property is text until evaluated
    text = refused(tmp_path, '  <xacro:property name="x" value="1"/>\n  <a v="${f\'{x:>9}\'}"/>')
    assert "invalid expression" in text  # '}' ends the ${}: as in xacro


def test_builtins_a_function_is_given_are_checked_too(tmp_path: Path) -> None:
    text = refused(tmp_path, '  <a v="${list(map(python.getattr, [1]))}"/>')
    assert "'getattr' is not available" in text


def test_eval_substitution_uses_the_same_sandbox() -> None:
    # ($(…) cannot hold ')': the calls themselves are tested on the interpreter)
    with pytest.raises(XacroError, match="double underscore"):
        expand('<a v="$(eval __import__)"/>')
    with pytest.raises(XacroError, match="name 'vars' is not defined"):
        expand('<a v="$(eval vars)"/>')
    with pytest.raises(XacroError, match="attribute 'mro' of a type value is not available"):
        expand('<a v="$(eval str.mro)"/>')
    with pytest.raises(XacroError, match="9 \\*\\* 387420489 is too large"):
        expand('<a v="$(eval 9**9**9)"/>')
    assert 'v="3"' in expand('<a v="$(eval 1 + 2)"/>')


@pytest.mark.parametrize("name", ["open", "eval", "exec", "compile", "getattr", "globals"])
def test_no_builtins_beyond_the_exposed_ones(name: str) -> None:
    with pytest.raises(XacroError, match=f"name '{name}' is not defined"):
        expand(f'<a v="${{{name}}}"/>')


@pytest.mark.parametrize(
    ("expr", "result"),
    [
        ("[x*2 for x in python.range(4) if x]", "[2, 4, 6]"),
        ("(lambda x, y=2: x + y)(1)", "3"),
        ("python.sorted([3, 1, 2], key=lambda v: -v)", "[3, 2, 1]"),
        ("list(map(lambda v: v + 1, [1, 2]))", "[2, 3]"),
        ("python.sum(x for x in [1, 2, 3])", "6"),
        ("', '.join(['a', 'b']).upper()", "A, B"),
        ("'a,b;c'.split(',')[1].replace(';', '-')", "b-c"),
        ("'%s-%03d' % ('a', 7)", "a-007"),
        ("(3).bit_length() + (1.5).is_integer()", "2"),
        ("xacro.tokenize('a b,c')[-1]", "c"),
        ("[*python.range(2), 4][1:]", "[1, 4]"),
        ("1 if 2 in [1, 2] else 0", "1"),
        ("math.factorial(20)", "2432902008176640000"),
        ("2**100", "1267650600228229401496703205376"),
        ("'-' * 3", "---"),
        ("xacro.dotify(python.dict(a=python.dict(b=3))).a.b", "3"),
    ],
)
def test_what_xacro_documents_still_works(expr: str, result: str) -> None:
    assert f'v="{result}"' in expand(f'<a v="${{{expr}}}"/>')


# --- bounded work ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("expr", "message"),
    [
        ("9**9**9", "9 ** 387420489 is too large (more than 32,768 bits)"),
        ("10**100000", "10 ** 100000 is too large"),
        ("1 &lt;&lt; 10**9", "shifting by 1000000000 is too large"),
        ("2**30000 * 2**30000", "the product is too large"),
        ("'ab' * 10**8", "repeating a string 100,000,000 times"),
        ("[0] * 10**8", "repeating a sequence 100,000,000 times"),
        ("[[[0] * 1000] * 1000] * 100", "repeating a nested sequence 100 times"),
        ("python.range(10**9)", "a range of 1,000,000,000 items is too large"),
        ("math.factorial(10**6)", "factorial(1000000) is too large"),
        ("math.comb(10**6, 5 * 10**5)", "is too large"),
        (
            "python.sum(python.sum(python.range(10**6)) for i in python.range(100))",
            "the expression does too much work (more than 10,000,000 steps)",
        ),
        ("(lambda f: f(f))(lambda f: f(f))", "lambdas calling each other deeper than 100 levels"),
        ("'a'.ljust(10**9)", "a width of 1,000,000,000 is more than 10,000,000 characters"),
        ("('a' * 1000).replace('a', 'b' * 100000)", "replace() would give more than"),
        ("python.sum([[1], [2]], [])", "sum() adds numbers only"),
        ("int('9' * 6000)", "int() of a 6,000-character string is too large"),
        ("-" * 6000 + "1", "nested too deeply to parse"),
        ("(" * 250 + "1" + ")" * 250, "too many nested parentheses"),
        ("[" * 99 + "]" * 99 + " + " + "-" * 200 + "1", "nested more than 100 levels deep"),
    ],
)
def test_work_is_bounded(tmp_path: Path, expr: str, message: str) -> None:
    text = refused(tmp_path, f'  <link name="${{{expr}}}"/>')
    assert text.startswith("evil.xacro:2:"), text[:200]
    assert message in text


def test_sizes_that_grow_through_properties_are_bounded(tmp_path: Path) -> None:
    # each property doubles what the last held: by sharing (lists) or by squaring (ints)
    lists = "\n".join(
        f'  <xacro:property name="p{i + 1}" value="${{[p{i}, p{i}]}}"/>' for i in range(30)
    )
    text = refused(
        tmp_path, f'  <xacro:property name="p0" value="${{[1]}}"/>\n{lists}\n  <a v="${{p30}}"/>'
    )
    assert "is too large: more than 10,000,000 elements" in text
    ints = "\n".join(
        f'  <xacro:property name="n{i + 1}" value="${{n{i} * n{i}}}"/>' for i in range(30)
    )
    text = refused(
        tmp_path, f'  <xacro:property name="n0" value="3"/>\n{ints}\n  <a v="${{n30}}"/>'
    )
    assert "the product is too large" in text


def test_long_flat_expressions_need_no_depth() -> None:
    expr = "+".join(["1"] * 3000)
    assert 'v="3000"' in expand(f'<a v="${{{expr}}}"/>')
    assert 'v="True"' in expand(f'<a v="${{{" and ".join(["1"] * 3000)} == 1}}"/>')


# --- YAML ----------------------------------------------------------------------------------------


def test_yaml_alias_bombs_are_refused_before_they_are_built(tmp_path: Path) -> None:
    lines = ['a: &a ["x", "x", "x", "x", "x", "x", "x", "x", "x", "x"]']
    for i, name in enumerate("bcdefghi"):
        prev = "abcdefghi"[i]
        lines.append(f"{name}: &{name} [{', '.join(['*' + prev] * 10)}]")
    (tmp_path / "bomb.yaml").write_text("\n".join(lines) + "\n")
    text = refused(tmp_path, "  <a v=\"${xacro.load_yaml('bomb.yaml')}\"/>")
    # at the first value that grows past the limit, and where it was loaded
    assert text.startswith(
        f"{tmp_path}/bomb.yaml:6:4: error: invalid YAML: YAML aliases here expand"
    )
    assert "loaded by xacro.load_yaml at evil.xacro:2:3" in text


def test_recursive_yaml_is_refused(tmp_path: Path) -> None:
    (tmp_path / "loop.yaml").write_text("a: &a [1, *a]\n")
    text = refused(tmp_path, "  <a v=\"${xacro.load_yaml('loop.yaml')}\"/>")
    assert text.startswith(f"{tmp_path}/loop.yaml:1:4: error: invalid YAML: a YAML alias refers to")


def test_a_yaml_fifo_is_refused_at_the_expression_not_waited_on(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "cfg.yaml")
    text = refused(tmp_path, "  <a v=\"${xacro.load_yaml('cfg.yaml')}\"/>")
    assert text.startswith(
        f"evil.xacro:2:3: error: cannot load YAML file {tmp_path}/cfg.yaml: it is a FIFO"
    )


def test_yaml_that_is_not_utf8_is_refused_at_its_byte(tmp_path: Path) -> None:
    (tmp_path / "cfg.yaml").write_bytes(b"a: 1\nb: \xff\n")
    text = refused(tmp_path, "  <a v=\"${xacro.load_yaml('cfg.yaml')}\"/>")
    assert text.startswith(f"{tmp_path}/cfg.yaml:2:4: error: cannot load YAML file {tmp_path}/")
    assert "it is not UTF-8 text (byte 0xff)" in text
    assert "loaded by xacro.load_yaml at evil.xacro:2:3" in text


def test_yaml_with_shared_parts_loads_and_prints_as_xacro_does(tmp_path: Path) -> None:
    (tmp_path / "cfg.yaml").write_text("base: &b {r: 0.1}\narm: {link: *b, n: 2}\n")
    body = (
        '<xacro:property name="cfg" value="${xacro.load_yaml(\'cfg.yaml\')}"/>'
        '<a v="${cfg.arm.link.r * cfg.arm.n}" k="${python.sorted(cfg.keys())}"/>'
    )
    path = tmp_path / "ok.xacro"
    path.write_text(f"<robot {NS}>{body}</robot>")
    out = process_file(path)
    assert 'v="0.2"' in out
    assert "k=\"['arm', 'base']\"" in out


# --- XML ---------------------------------------------------------------------------------------


def test_external_entities_are_never_loaded(tmp_path: object) -> None:
    doc = (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
        f"<robot {NS}><a>&x;</a></robot>"
    )
    with pytest.raises(ParseError):
        process_string(doc)


def test_dtd_with_system_id_is_refused() -> None:
    doc = f'<!DOCTYPE robot SYSTEM "http://example.com/r.dtd"><robot {NS}/>'
    with pytest.raises(ParseError, match="external DTDs are not loaded"):
        process_string(doc)


def test_entity_expansion_bombs_are_refused() -> None:
    bomb = (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa">'
        '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>'
        f"<robot {NS}>&b;</robot>"
    )
    with pytest.raises(ParseError):
        process_string(bomb)


# --- reading outside the model's packages ------------------------------------------------------


def _package(root: Path, name: str) -> Path:
    (root / name / "urdf").mkdir(parents=True)
    (root / name / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return root / name


def test_reads_outside_the_package_roots_are_named_and_strict_refuses(tmp_path: Path) -> None:
    from belvedere.description.xacro import expand_file
    from belvedere.packages import PackageIndex

    pkg = _package(tmp_path / "ws", "robot_pkg")
    other = _package(tmp_path / "ws", "parts_pkg")
    (other / "urdf" / "part.xacro").write_text(f'<robot {NS}><link name="part"/></robot>')
    (pkg / "config.yaml").write_text("n: 1\n")
    secret = tmp_path / "secret.yaml"
    secret.write_text("n: 2\n")
    robot = pkg / "urdf" / "robot.xacro"
    robot.write_text(
        f'<robot name="r" {NS}>\n'
        '  <xacro:property name="own" value="${xacro.load_yaml(\'../config.yaml\')}"/>\n'
        '  <xacro:include filename="$(find parts_pkg)/urdf/part.xacro"/>\n'
        f'  <xacro:property name="s" value="${{xacro.load_yaml(\'{secret}\')}}"/>\n'
        '  <link name="l${own.n}${s.n}"/>\n'
        "</robot>\n"
    )
    packages = PackageIndex([tmp_path / "ws"])
    expansion = expand_file(robot, packages=packages, on_warning=lambda w: None)
    assert '<link name="l12"/>' in expansion.to_xml()  # read, as xacro reads it
    (warning,) = [w for w in expansion.warnings if "outside" in w.message]
    assert str(warning).startswith(f"{robot}:4:3: warning: reads {secret}, outside the model")
    assert str(pkg) in warning.message  # the roots it resolved are named
    assert str(other) in warning.message

    with pytest.raises(XacroError, match=rf"refusing to read {secret}: it is outside") as info:
        expand_file(robot, packages=packages, strict=True)
    assert info.value.location is not None
    assert info.value.location.line == 4


def test_includes_outside_the_package_roots_are_named(tmp_path: Path) -> None:
    from belvedere.description.xacro import expand_file

    pkg = _package(tmp_path, "robot_pkg")
    (tmp_path / "loose.xacro").write_text(f'<robot {NS}><link name="loose"/></robot>')
    robot = pkg / "urdf" / "robot.xacro"
    robot.write_text(
        f'<robot name="r" {NS}>\n  <xacro:include filename="../../loose.xacro"/>\n</robot>\n'
    )
    warnings = expand_file(robot, on_warning=lambda w: None).warnings
    assert next(str(w) for w in warnings if "outside" in w.message).startswith(
        f"{robot}:2:3: warning: reads {tmp_path / 'loose.xacro'}, outside the model's package"
    )
    with pytest.raises(XacroError, match=r"robot\.xacro:2:3: error: refusing to read"):
        expand_file(robot, strict=True)


def test_strict_on_the_command_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from belvedere.cli import main

    pkg = _package(tmp_path, "robot_pkg")
    robot = pkg / "urdf" / "robot.xacro"
    robot.write_text(
        f'<robot name="r" {NS}>\n'
        f"  <link name=\"${{xacro.load_yaml('{tmp_path / 'x.yaml'}')}}\"/>\n</robot>\n"
    )
    (tmp_path / "x.yaml").write_text("1\n")
    assert main(["xacro", str(robot)]) == 0
    assert "outside the model's package roots" in capsys.readouterr().err
    assert main(["xacro", "--strict", str(robot)]) == 1
    assert "error: refusing to read" in capsys.readouterr().err
    assert main(["check", "--strict", str(robot)]) == 1
    assert "error: refusing to read" in capsys.readouterr().err
