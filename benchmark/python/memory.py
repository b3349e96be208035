"""Peak memory of a process as Linux counts it (resident set, C++ allocations included), which
tracemalloc's count of Python's own allocations would miss."""


def resident_bytes():
    """(current, peak) resident set size of this process, from /proc/self/status."""
    fields = {}
    with open("/proc/self/status") as status:
        for line in status:
            key, _, value = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                fields[key] = int(value.split()[0]) * 1024
    return fields["VmRSS"], fields["VmHWM"]


def reset_peak():
    """Starts a new peak: the kernel sets VmHWM back to the current resident size."""
    with open("/proc/self/clear_refs", "w") as clear:
        clear.write("5")
