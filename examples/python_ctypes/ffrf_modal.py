#!/usr/bin/env python3
"""Runs a modal case through the installed ffrf C API from Python (ctypes, no compiler) and prints
every body's natural frequencies, one line per mode: "<body> <mode> <frequency in Hz, %.17g>".

The library is the installed libffrf.so found through pkg-config (`pkg-config --variable=libdir
ffrf`; set PKG_CONFIG_PATH=<prefix>/lib/pkgconfig for a private prefix) or given by --library.
Nothing is written to disk (output_dir NULL). Exit status: 0, or the ffrf status of the failed call.
"""
import argparse
import ctypes
import os
import subprocess
import sys

FFRF_OK = 0


class FfrfError(RuntimeError):
    """A failed ffrf call: its status code and the message the handle keeps."""

    def __init__(self, call, status, message):
        super().__init__(f'{call}: status {status}: {message}')
        self.status = status


def find_library():
    """libffrf.so.<SOVERSION> in pkg-config's libdir (the name a program records at link time)."""
    libdir = subprocess.run(['pkg-config', '--variable=libdir', 'ffrf'], check=True,
                            capture_output=True, text=True).stdout.strip()
    names = sorted(n for n in os.listdir(libdir) if n.startswith('libffrf.so'))
    if not names:
        raise FileNotFoundError(f'no libffrf.so in {libdir}: ffrf was installed without '
                                '-DBUILD_SHARED_LIBS=ON')
    return os.path.join(libdir, 'libffrf.so.0' if 'libffrf.so.0' in names else names[0])


def load(path):
    """The C API's entry points with their prototypes (include/ffrf.h)."""
    lib = ctypes.CDLL(path)
    handle = ctypes.c_void_p            # ffrf_case *, opaque
    c_int_p = ctypes.POINTER(ctypes.c_int)
    prototypes = {
        'ffrf_version': (None, [c_int_p, c_int_p, c_int_p]),
        'ffrf_case_open': (ctypes.c_int, [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p,
                                          ctypes.POINTER(handle)]),
        'ffrf_case_run': (ctypes.c_int, [handle]),
        'ffrf_body_count': (ctypes.c_int, [handle, c_int_p]),
        'ffrf_body_name': (ctypes.c_int, [handle, ctypes.c_int, ctypes.c_char_p, ctypes.c_size_t]),
        'ffrf_body_frequencies': (ctypes.c_int, [handle, ctypes.c_int,
                                                 ctypes.POINTER(ctypes.c_double), ctypes.c_int,
                                                 c_int_p]),
        'ffrf_last_error': (ctypes.c_char_p, [handle]),
        'ffrf_case_close': (None, [handle]),
    }
    for name, (restype, argtypes) in prototypes.items():
        function = getattr(lib, name)
        function.restype = restype
        function.argtypes = argtypes
    return lib


class Case:
    """An ffrf case handle; closed on leaving the `with` block."""

    def __init__(self, lib, case_file, mesh_dir=None):
        self.lib = lib
        self.handle = ctypes.c_void_p()
        status = lib.ffrf_case_open(case_file.encode(), mesh_dir.encode() if mesh_dir else None,
                                    None, ctypes.byref(self.handle))
        self._check('ffrf_case_open', status)

    def _check(self, call, status):
        if status != FFRF_OK:
            message = self.lib.ffrf_last_error(self.handle) if self.handle else b'(no handle)'
            raise FfrfError(call, status, message.decode())

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.lib.ffrf_case_close(self.handle)
        self.handle = ctypes.c_void_p()

    def run(self):
        self._check('ffrf_case_run', self.lib.ffrf_case_run(self.handle))

    def bodies(self):
        n = ctypes.c_int()
        self._check('ffrf_body_count', self.lib.ffrf_body_count(self.handle, ctypes.byref(n)))
        return range(n.value)

    def body_name(self, body):
        buffer = ctypes.create_string_buffer(256)
        self._check('ffrf_body_name',
                    self.lib.ffrf_body_name(self.handle, body, buffer, len(buffer)))
        return buffer.value.decode()

    def frequencies(self, body):
        count = ctypes.c_int()
        # a NULL array with capacity 0 asks for the size
        self._check('ffrf_body_frequencies', self.lib.ffrf_body_frequencies(
            self.handle, body, None, 0, ctypes.byref(count)))
        hz = (ctypes.c_double * count.value)()
        self._check('ffrf_body_frequencies', self.lib.ffrf_body_frequencies(
            self.handle, body, hz, count.value, ctypes.byref(count)))
        return list(hz)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('case', help='case file (.nml)')
    parser.add_argument('mesh_dir', nargs='?', help='folder of the mesh files')
    parser.add_argument('--library', help='path of libffrf.so (default: from pkg-config)')
    args = parser.parse_args()
    lib = load(args.library or find_library())
    version = [ctypes.c_int() for _ in range(3)]
    lib.ffrf_version(*(ctypes.byref(v) for v in version))
    print(f'# ffrf {".".join(str(v.value) for v in version)}, case {args.case}')
    try:
        with Case(lib, args.case, args.mesh_dir) as case:
            case.run()
            for body in case.bodies():
                name = case.body_name(body)
                for mode, hz in enumerate(case.frequencies(body), start=1):
                    print(f'{name} {mode} {hz:.17g}')
    except FfrfError as error:
        print(f'ffrf_modal.py: {error}', file=sys.stderr)
        return error.status
    return 0


if __name__ == '__main__':
    sys.exit(main())
