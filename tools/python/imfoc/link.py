"""The serial port to the drive, with the frame decoder on its input, and how a command
of the PC tool ends when it cannot do its job (Failure: one line and an exit status)."""
import time

from .protocol import FrameDecoder, command_frame

EXIT_OK, EXIT_DRIVE, EXIT_USAGE, EXIT_PORT = 0, 1, 2, 3


class Failure(Exception):
    """Ends the command with a one-line reason and an exit status."""

    def __init__(self, reason, status):
        super().__init__(reason)
        self.status = status


def reason_text(e):
    """An exception's first line (its class name if it has no text)."""
    text = str(e).strip() or e.__class__.__name__
    return text.splitlines()[0]


class Link:
    """The serial port with the frame decoder on its input."""

    def __init__(self, port, baud):
        try:
            import serial
        except ImportError:
            raise Failure("pyserial is not installed (pip install pyserial, or "
                          "tools/install_deps.sh)", EXIT_USAGE) from None
        self._serial = serial
        self.port = port
        try:
            self.ser = serial.Serial(port, baudrate=baud, bytesize=8, parity="N", stopbits=1,
                                     timeout=0.05, write_timeout=2.0)
            self.ser.reset_input_buffer()
        except (serial.SerialException, OSError, ValueError) as e:
            raise Failure(f"cannot open {port}: {reason_text(e)}", EXIT_PORT) from None
        self.decoder = FrameDecoder()
        self.t_last_frame = None

    def read(self):
        """The frames completed by what arrived within ~50 ms ([] if none)."""
        try:
            data = self.ser.read(max(1, self.ser.in_waiting))
        except (self._serial.SerialException, OSError) as e:
            raise Failure(f"{self.port}: the port vanished ({reason_text(e)})",
                          EXIT_PORT) from None
        frames = self.decoder.feed(data)
        if frames:
            self.t_last_frame = time.monotonic()
        return frames

    def send(self, name):
        try:
            self.ser.write(command_frame(name))
            self.ser.flush()
        except (self._serial.SerialException, OSError) as e:
            raise Failure(f"{self.port}: cannot send ({reason_text(e)})", EXIT_PORT) from None

    def close(self):
        try:
            self.ser.close()
        except (self._serial.SerialException, OSError):
            pass
