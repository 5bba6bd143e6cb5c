"""A minimal writer of the kernel's initramfs format (cpio "newc", SVR4 without checksums), so
the image needs no host `cpio` and no root: device nodes such as /dev/console are plain entries."""

import stat

MAGIC = b"070701"


def _pad4(n):
    return (4 - n % 4) % 4


def _header(ino, mode, size, namesize, rdev=(0, 0), nlink=1):
    fields = [ino, mode, 0, 0, nlink, 0, size, 0, 0, rdev[0], rdev[1], namesize, 0]
    return MAGIC + b"".join(b"%08X" % f for f in fields)


class Writer:
    """Entries are written in the order given; parents must come before their children."""

    def __init__(self, out):
        self.out = out
        self.ino = 1

    def _entry(self, name, mode, data=b"", rdev=(0, 0), nlink=1):
        encoded = name.encode() + b"\0"
        head = _header(self.ino, mode, len(data), len(encoded), rdev, nlink)
        self.ino += 1
        self.out.write(head + encoded + b"\0" * _pad4(len(head) + len(encoded)))
        self.out.write(data + b"\0" * _pad4(len(data)))

    def directory(self, name, perm=0o755):
        self._entry(name, stat.S_IFDIR | perm, nlink=2)

    def file(self, name, data, perm=0o644):
        self._entry(name, stat.S_IFREG | perm, data)

    def symlink(self, name, target):
        self._entry(name, stat.S_IFLNK | 0o777, target.encode())

    def chardev(self, name, major, minor, perm=0o600):
        self._entry(name, stat.S_IFCHR | perm, rdev=(major, minor))

    def finish(self):
        self._entry("TRAILER!!!", 0, nlink=1)
        # The kernel reads the archive in 512-byte blocks like cpio does: pad to a full block.
        pos = self.out.tell()
        self.out.write(b"\0" * ((512 - pos % 512) % 512))
