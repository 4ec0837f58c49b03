"""tools/target/iqmath_lib_sizes.py: the COFF archive reader that measured
bench_size.py's TI IQmath sizes, on archives built here byte by byte from the
format's definition (TI SPRAAO8), since TI's library is not in the tree."""
import struct
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "target"))
import iqmath_lib_sizes as ils  # noqa: E402


def coff(sections, target=0x009D):
    """A C28x COFF2 object with the given [(name bytes, size)] section headers."""
    head = struct.pack("<HHIIIHHH", 0x00C2, len(sections), 0, 0, 0, 0, 0, target)
    body = b"".join(struct.pack("<8sIIIIIIIIIHH", n, 0, 0, s, 0, 0, 0, 0, 0, 0, 0, 0)
                    for n, s in sections)
    return head + body


def archive(members):
    """A GNU ar archive; names longer than 15 characters go to the // table."""
    longnames = b"".join(n.encode() + b"/\n" for n, _ in members if len(n) > 15)
    out = [b"!<arch>\n"]

    def member(name, data):
        hdr = f"{name:<16}{0:<12}{0:<6}{0:<6}{644:<8}{len(data):<10}`\n".encode()
        assert len(hdr) == 60
        return hdr + data + (b"\n" if len(data) & 1 else b"")
    if longnames:
        out.append(member("//", longnames))
    off = 0
    for name, data in members:
        if len(name) > 15:
            out.append(member(f"/{off}", data))
            off += len(name) + 2
        else:
            out.append(member(name + "/", data))
    return b"".join(out)


def test_sizes_per_operation_and_q():
    debug = b"\0\0\0\0\x10\0\0\0"   # a long name: an offset into the string table
    lib = archive([
        ("IQ24div.obj", coff([(b".text", 0), (debug, 481), (b"IQmath", 71)])),
        ("IQ30div.obj", coff([(b"IQmath", 71), (b".data", 3)])),
        ("IQ29atan2PU.obj", coff([(b"IQmath", 136)])),   # > 15 characters: // table
        ("IQmathTables.obj", coff([(b"IQmathTables", 2896)])),   # not a function
    ])
    assert ils.sizes(lib) == {"div": {24: 71, 30: 71}, "atan2PU": {29: 136}}


def test_refuses_what_is_not_a_c28x_coff_library():
    with pytest.raises(ValueError):
        ils.sizes(b"not an archive")
    with pytest.raises(ValueError):
        ils.sizes(archive([("IQ24div.obj", coff([(b"IQmath", 71)], target=0x0099))]))
