"""The report scripts' one way to write a file, as nuld's C++ writer does
(sampler/io/atomic_file.h): a hidden temporary file beside the destination,
flushed to the disk, then renamed over it. A failure removes the temporary
file, leaves an earlier file as it was, and ends the script with exit 1 and
one line naming the destination and the system's reason."""
import os
import sys


def _temporary(path):
    head, tail = os.path.split(path)
    stem, ext = os.path.splitext(tail)
    # The extension stays last: matplotlib picks the format by it.
    return os.path.join(head, f".{stem}.tmp{os.getpid()}{ext}")


def _commit(tmp, path, write):
    try:
        write(tmp)
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        sys.exit(f"{os.path.basename(sys.argv[0])}: {path}: cannot write the file "
                 f"({e.strerror or e})")


def write_text(path, text):
    def write(tmp):
        with open(tmp, "w") as f:
            f.write(text)
    _commit(_temporary(path), path, write)


def save_figure(fig, path, **options):
    _commit(_temporary(path), path, lambda tmp: fig.savefig(tmp, **options))
