"""A user's OpenCV script with a window, run as belvedere runs scripts (``belvedere run
SCRIPT`` in a process of its own, beside the test's graph), and what it prints, line by line,
as it comes."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

from tests.waiting import DEADLINE, wait_until

__all__ = ["PICTURE_BGR", "WINDOW", "WindowScript"]

WINDOW = "keys test"
"""The script's window: its topic is /image_window/keys_test."""
PICTURE_BGR = ((0, 0, 255), (0, 255, 0), (255, 0, 0))
"""The picture's three upright bands, left to right, as OpenCV's BGR: red, green, blue."""

SCRIPT = """\
import cv2
import numpy as np
import rospy

rospy.init_node("window_keys")
print("no window:", cv2.waitKey(0), flush=True)
picture = np.zeros((240, 360, 3), np.uint8)
for band, bgr in enumerate({bands}):
    picture[:, band * 120 : (band + 1) * 120] = bgr
cv2.imshow({window!r}, picture)
print("shown:", cv2.waitKey(20), flush=True)
keys = []
while len(keys) < {count} and not rospy.is_shutdown():
    cv2.imshow({window!r}, picture)  # as a camera callback shows each frame
    key = cv2.waitKey(100)
    if key != -1:
        keys.append(key)
        print("key:", key, flush=True)
if {destroy}:
    cv2.destroyAllWindows()
    print("destroyed:", cv2.waitKey(0), flush=True)
    rospy.spin()
else:
    print("waiting", flush=True)
    print("ended:", cv2.waitKey(0), flush=True)
"""


class WindowScript:
    """The script, showing the bands in window :data:`WINDOW` and printing the first
    ``count`` keys its ``cv2.waitKey`` returns; then it destroys its windows and spins
    (``destroy``) or waits in ``cv2.waitKey(0)`` for a key that never comes."""

    def __init__(self, tmp_path: Path, *, count: int, destroy: bool) -> None:
        path = tmp_path / "window_keys.py"
        path.write_text(
            SCRIPT.format(window=WINDOW, bands=PICTURE_BGR, count=count, destroy=destroy)
        )
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "belvedere", "run", str(path)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.lines: list[str] = []
        self.errors: list[str] = []
        self._readers = [
            threading.Thread(target=self._read, args=(stream, into), daemon=True)
            for stream, into in ((self.proc.stdout, self.lines), (self.proc.stderr, self.errors))
        ]
        for reader in self._readers:
            reader.start()

    @staticmethod
    def _read(stream: object, into: list[str]) -> None:
        for line in stream:  # type: ignore[attr-defined]
            into.append(line.rstrip("\n"))

    def wait_for(self, prefix: str) -> str:
        """The first line the script printed that starts with ``prefix`` (waited for)."""

        def printed() -> str:
            found = [line for line in self.lines if line.startswith(prefix)]
            if not found and self.proc.poll() is not None:
                msg = f"the script ended ({self.proc.returncode}) first: " + "\n".join(
                    self.lines + self.errors
                )
                raise AssertionError(msg)
            return found[0] if found else ""

        line: str = wait_until(
            printed,
            what=f"the script to print {prefix!r}",
            detail=lambda: textwrap.shorten(" | ".join(self.lines + self.errors), 2000),
        )
        return line

    def stop(self) -> int:
        """Ctrl-C (unless it ended): its exit status."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        status = self.proc.wait(timeout=DEADLINE)
        for reader in self._readers:
            reader.join(timeout=DEADLINE)
        return status
