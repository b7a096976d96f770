"""The live view: latest obstacle, rates, link and clock health.

With rich and a terminal on stderr it is a live table redrawn a few times a second; on a
pipe, a log file or without rich it degrades to one plain status line every few seconds,
so a CI log or `... 2> run.log` stays readable.
"""

from __future__ import annotations

import logging
import sys
import time
from collections import deque
from dataclasses import dataclass, field
from typing import Any, TextIO

from obstacle_fusion.fusion import ObstacleRecord

log = logging.getLogger(__name__)


class RateMeter:
    """Events per second over a sliding window."""

    def __init__(self, window_s: float = 2.0) -> None:
        self.window_s = window_s
        self._times: deque[float] = deque()

    def tick(self, t: float | None = None) -> None:
        self._times.append(time.monotonic() if t is None else t)

    def rate(self, now: float | None = None) -> float:
        now = time.monotonic() if now is None else now
        while self._times and self._times[0] < now - self.window_s:
            self._times.popleft()
        if len(self._times) < 2:
            return 0.0
        span = max(now - self._times[0], 1e-9)
        return (len(self._times) - 1) / span if span > 0 else 0.0


@dataclass
class Status:
    """Everything the view shows; the app fills it in."""

    mode: str = ""
    latest: ObstacleRecord | None = None
    link: dict[str, Any] = field(default_factory=dict)
    fusion: dict[str, Any] = field(default_factory=dict)
    clock: dict[str, Any] = field(default_factory=dict)
    rates: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def _fmt(v: float | None, unit: str = "m", digits: int = 3) -> str:
    return "-" if v is None else f"{v:.{digits}f} {unit}"


def mode_label(mode: str) -> str:
    """The emulated robot says so plainly: nobody should mistake its numbers for a robot's."""
    return "EMULATED robot" if mode == "emulator" else mode


def status_line(s: Status) -> str:
    r = s.latest
    obst = (
        "no frame yet"
        if r is None
        else (
            f"{r.status} d={_fmt(r.distance_m)} h={_fmt(r.height_m)} w={_fmt(r.width_m)}"
            f"{' ALERT' if r.alert else ''}"
        )
    )
    link = s.link
    return (
        f"[{mode_label(s.mode)}] {obst} | fps {s.rates.get('frames', 0):.1f} ranges/s "
        f"{s.rates.get('ranges', 0):.1f} | link {'up' if link.get('connected') else 'DOWN'} "
        f"frames {link.get('frames', 0)} crc {link.get('crc_errors', 0)} gaps "
        f"{link.get('seq_gaps', 0)} overruns {link.get('device_tx_overruns', 0)} reconnects "
        f"{link.get('reconnects', 0)} | paired {100 * s.fusion.get('paired_fraction', 0):.1f}% "
        f"unpaired {s.fusion.get('unpaired', 0)} | clock drift "
        f"{s.clock.get('drift_ppm', float('nan')):.0f} ppm "
        f"+-{1e3 * s.clock.get('uncertainty_s', float('nan')):.2f} ms"
    )


class ConsoleView:
    """Call update(status) as often as you like; it redraws at most ``refresh_hz``."""

    def __init__(
        self,
        stream: TextIO | None = None,
        *,
        live: bool | None = None,
        refresh_hz: float = 4.0,
        plain_interval_s: float = 5.0,
    ) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.refresh_s = 1.0 / refresh_hz
        self.plain_interval_s = plain_interval_s
        self._last = 0.0
        self._live: Any = None
        self._console: Any = None
        want_live = self.stream.isatty() if live is None else live
        if want_live:
            try:
                from rich.console import Console
                from rich.live import Live

                self._console = Console(file=self.stream)
                self._live = Live(console=self._console, auto_refresh=False, transient=False)
                self._live.start()
            except ImportError:
                self._live = None
        self.plain = self._live is None
        self.lines = 0

    def update(self, status: Status, force: bool = False) -> None:
        now = time.monotonic()
        interval = self.plain_interval_s if self.plain else self.refresh_s
        if not force and now - self._last < interval:
            return
        self._last = now
        if self.plain:
            self.stream.write(status_line(status) + "\n")
            self.stream.flush()
        else:
            self._live.update(self._table(status), refresh=True)
        self.lines += 1

    def _table(self, s: Status) -> Any:
        from rich.table import Table

        t = Table(title=f"obstacle-fusion  [{mode_label(s.mode)}]", show_header=False, expand=False)
        t.add_column("what", style="bold")
        t.add_column("value")
        r = s.latest
        if r is None:
            t.add_row("obstacle", "waiting for the first frame")
        else:
            style = "bold red" if r.alert else ("green" if r.status == "ok" else "yellow")
            t.add_row("obstacle", f"[{style}]{r.status}{'  STOP' if r.alert else ''}[/]")
            t.add_row("distance", _fmt(r.distance_m))
            t.add_row("height x width", f"{_fmt(r.height_m)} x {_fmt(r.width_m)}")
            t.add_row("confidence", f"{r.confidence:.2f}")
            t.add_row("pairing", f"{r.pairing} ({_fmt(r.pair_dt_s, 's', 4)})")
            lat = r.latency_s
            t.add_row("latency", "-" if lat is None else f"{lat * 1e3:.1f} ms")
        t.add_row(
            "rates",
            f"frames {s.rates.get('frames', 0):.1f}/s  ranges {s.rates.get('ranges', 0):.1f}/s"
            f"  records {s.rates.get('records', 0):.1f}/s",
        )
        link = s.link
        t.add_row(
            "link",
            f"{'[green]up[/]' if link.get('connected') else '[red]DOWN[/]'} {link.get('port')}  "
            f"frames {link.get('frames', 0)}  crc {link.get('crc_errors', 0)}  "
            f"gaps {link.get('seq_gaps', 0)}  overruns {link.get('device_tx_overruns', 0)}  "
            f"reconnects {link.get('reconnects', 0)}",
        )
        t.add_row(
            "fusion",
            f"paired {100 * s.fusion.get('paired_fraction', 0):.1f}%  "
            f"unpaired {s.fusion.get('unpaired', 0)}  published {s.fusion.get('published', 0)}",
        )
        if s.clock:
            t.add_row(
                "clock",
                f"{s.clock.get('source')}  drift {s.clock.get('drift_ppm', 0):.0f} ppm  "
                f"+-{1e3 * s.clock.get('uncertainty_s', 0):.3f} ms",
            )
        for note in s.notes[-3:]:
            t.add_row("note", note)
        return t

    def close(self) -> None:
        if self._live is not None:
            self._live.stop()
            self._live = None
            self.stream.write("\n")  # the table's border ends without one
            self.stream.flush()
