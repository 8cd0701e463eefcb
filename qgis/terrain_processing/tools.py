"""Running the toolkit's command-line tools from Processing: where they are, their progress
fed to QGIS's progress bar, cancel ending them cleanly, their one-line error shown."""
import os
import re
import shutil
import signal
import subprocess
import threading
import time

from qgis.core import QgsProcessingException

# The tools' progress on stderr, as GDAL's: "step: 0...10...20 ... 100 - done."
_PERCENT = re.compile(r"(\d{1,3})(?:\.\.\.| - done)")


def tool_path(name):
    """The tool `name`: in $TERRAIN_BIN when set, else on the PATH."""
    directory = os.environ.get("TERRAIN_BIN", "")
    if directory:
        path = os.path.join(directory, name)
        if os.access(path, os.X_OK):
            return path
        raise QgsProcessingException(
            f"{name} is not in TERRAIN_BIN ({directory}): build or install the toolkit there")
    path = shutil.which(name)
    if not path:
        raise QgsProcessingException(
            f"{name} is not on the PATH: install the toolkit, or set TERRAIN_BIN to its bin/")
    return path


def _error_line(stderr_text, name, code):
    """The tool's one-line error: its last line that is not progress."""
    lines = [l.strip() for l in re.split(r"[\r\n]", stderr_text) if l.strip()]
    lines = [l for l in lines if not _PERCENT.search(l) and not l.startswith("warning")]
    return lines[-1] if lines else f"{name} failed (exit code {code})"


def run_tool(name, args, feedback, share=(0.0, 100.0)):
    """Runs tool `name` with `args`; its progress moves QGIS's bar over `share` (percent).
    Cancel (feedback.isCanceled) interrupts it as Ctrl-C does: it stops, leaves no output,
    and QgsProcessingException says so. A failure raises its one-line error. Returns its
    stdout."""
    command = [tool_path(name)] + [str(a) for a in args]
    feedback.pushCommandInfo(" ".join(command))
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    err = []

    def read_stderr():
        while True:
            chunk = proc.stderr.read1(4096)
            if not chunk:
                return
            err.append(chunk.decode("utf-8", "replace"))

    out = []

    def read_stdout():
        out.append(proc.stdout.read().decode("utf-8", "replace"))

    readers = [threading.Thread(target=read_stderr, daemon=True),
               threading.Thread(target=read_stdout, daemon=True)]
    for t in readers:
        t.start()
    lo, hi = share
    shown, parsed = lo, 0
    canceled = False
    while proc.poll() is None:
        if feedback.isCanceled() and not canceled:
            canceled = True
            proc.send_signal(signal.SIGINT)  # the tools clean up and remove partial outputs
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
            break
        text = "".join(err)
        for mark in _PERCENT.finditer(text, parsed):  # every whole mark since, in order
            value = lo + (hi - lo) * min(int(mark.group(1)), 100) / 100.0
            if value > shown:
                shown = value
                feedback.setProgress(shown)
            parsed = mark.end()
        time.sleep(0.02)
    proc.wait()
    for t in readers:
        t.join(timeout=5)
    proc.stdout.close()
    proc.stderr.close()
    stderr_text = "".join(err)
    if canceled:
        raise QgsProcessingException(f"{name}: canceled")
    if proc.returncode != 0:
        raise QgsProcessingException(_error_line(stderr_text, name, proc.returncode))
    for line in stderr_text.splitlines():
        if line.startswith("warning") or ": warning" in line:
            feedback.pushWarning(line)
    feedback.setProgress(hi)
    return "".join(out)
