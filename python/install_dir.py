"""Prints where the sphray module goes under an install prefix, relative to it, so that this
Python finds it: python/CMakeLists.txt runs it at configure time.

    python3 python/install_dir.py PREFIX
"""
import os
import sys
import sysconfig

prefix = os.path.normpath(sys.argv[1])
version = f"{sys.version_info.major}.{sys.version_info.minor}"
if "deb_system" in sysconfig.get_scheme_names():
    # Debian's Python: the system's packages in /usr/lib/python3/dist-packages, the local
    # administrator's in /usr/local/lib/python3.X/dist-packages (both on sys.path).
    print("lib/python3/dist-packages" if prefix == "/usr" else f"lib/python{version}/dist-packages")
else:
    path = sysconfig.get_path("platlib", "posix_prefix", vars={"platbase": prefix, "base": prefix})
    print(os.path.relpath(path, prefix))
