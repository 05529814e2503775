"""Boots an nlsoft Cortex-M4F image in qemu-system-arm with its link's UART
on a pseudo-terminal and -icount shift=0 (1 ns of virtual time per
instruction), and finds the pty QEMU reports. Boards: mps2-an386 (UART0, the
first serial port) and stm32f4 (USART2 of -M netduinoplus2, the second)."""
import re
import shutil
import subprocess
import time

QEMU = "qemu-system-arm"
import os
ICOUNT = os.environ.get("NLSOFT_ICOUNT", "shift=0")


def available():
    return shutil.which(QEMU) is not None


class Qemu:
    def __init__(self, elf, timeout=10.0, board="mps2-an386"):
        machine = (["-M", "netduinoplus2", "-serial", "null", "-serial", "pty"] if board == "stm32f4"
                   else ["-M", "mps2-an386", "-serial", "pty"])
        self.proc = subprocess.Popen(
            [QEMU] + machine + ["-nographic", "-monitor", "none", "-icount", ICOUNT, "-kernel", elf],
            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.pty = None
        deadline = time.monotonic() + timeout
        # "char device redirected to /dev/pts/N (label serial0)"
        while self.pty is None and time.monotonic() < deadline:
            line = self.proc.stdout.readline()
            if not line:
                break
            m = re.search(r"redirected to (/dev/\S+)", line)
            if m:
                self.pty = m.group(1)
        if self.pty is None:
            self.close()
            raise RuntimeError("qemu-system-arm reported no pty for " + elf)

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
