"""Generated protocol files must be exactly what the generator makes from the spec."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[2]


def load_generator():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location(
        "protocol_gen", ROOT / "tools" / "protocol_gen.py"
    )
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    sys.modules["protocol_gen"] = module
    spec.loader.exec_module(module)
    return module


gen = load_generator()


@pytest.mark.parametrize("path", sorted(gen.outputs(gen.load_spec()).keys()), ids=lambda p: p.name)
def test_generated_file_is_up_to_date(path: Path) -> None:
    expected = gen.outputs(gen.load_spec())[path]
    assert path.exists(), f"{path} missing: run tools/protocol_gen.py"
    assert path.read_text(encoding="utf-8") == expected, (
        f"{path.relative_to(ROOT)} differs from the spec: run tools/protocol_gen.py, never edit it"
    )


def test_field_rename_changes_fingerprint(tmp_path: Path) -> None:
    spec_text = (ROOT / "protocol" / "spec.toml").read_text()
    changed = tmp_path / "spec.toml"
    changed.write_text(
        spec_text.replace('name = "sensor_id", type = "u8"', 'name = "sensor", type = "u8"')
    )
    assert gen.load_spec(changed).fingerprint != gen.load_spec().fingerprint


def test_field_change_changes_crc_extra(tmp_path: Path) -> None:
    spec_text = (ROOT / "protocol" / "spec.toml").read_text()
    changed = tmp_path / "spec.toml"
    changed.write_text(
        spec_text.replace('name = "echo_ticks", type = "u32"', 'name = "echo_ticks", type = "i32"')
    )
    old = {m.name: m.crc_extra for m in gen.load_spec().messages}
    new = {m.name: m.crc_extra for m in gen.load_spec(changed).messages}
    assert old["range"] != new["range"]
    assert {k: v for k, v in old.items() if k != "range"} == {
        k: v for k, v in new.items() if k != "range"
    }


def test_spec_errors_are_named(tmp_path: Path) -> None:
    spec_text = (ROOT / "protocol" / "spec.toml").read_text()
    bad = tmp_path / "spec.toml"
    bad.write_text(spec_text.replace("id = 0x44", "id = 0x43"))
    with pytest.raises(gen.SpecError, match="share id 0x43"):
        gen.load_spec(bad)
    bad.write_text(
        spec_text.replace(
            'type = "u16", unit = "ms" },\n  { name = "sensor_mask"',
            'type = "f16", unit = "ms" },\n  { name = "sensor_mask"',
            1,
        )
    )
    with pytest.raises(gen.SpecError, match="unknown type 'f16'"):
        gen.load_spec(bad)
