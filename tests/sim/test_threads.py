import pytest

from cloth_tui.sim import threads


class FakeClock:
    """The chooser's clocks, advanced only by the kernels below: the timings a test sets are
    the timings the chooser sees, however busy the machine running the test is."""

    def __init__(self):
        self.wall = 0.0
        self.cpu = 0.0

    def perf_counter(self):
        return self.wall

    def thread_time(self):
        return self.cpu

    def spend(self, seconds, on_cpu=True):
        self.wall += seconds
        if on_cpu:
            self.cpu += seconds


CLOCK = FakeClock()


class Recorder:
    """A kernel that records its calls and takes `seconds` of CPU time on the fake clock."""

    def __init__(self, name, seconds=1e-6):
        self.__name__ = name
        self.seconds = seconds
        self.calls = 0

    def __call__(self, *args):
        self.calls += 1
        CLOCK.spend(self.seconds)


@pytest.fixture(autouse=True)
def _cores(monkeypatch):
    global CLOCK
    CLOCK = FakeClock()
    monkeypatch.setattr(threads, "time", CLOCK)
    monkeypatch.setattr(threads, "usable_cores", lambda: 2)
    monkeypatch.setattr(threads, "load_average", lambda: 0.5)
    monkeypatch.setattr(threads, "runnable_now", lambda: 1)
    monkeypatch.delenv(threads.ENV_THREADS, raising=False)
    yield
    threads.force_single_thread(False)


def test_env_var_keeps_one_thread(monkeypatch):
    monkeypatch.setenv(threads.ENV_THREADS, "1")
    serial, parallel = Recorder("s"), Recorder("p")
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(300):
        choice()
    assert parallel.calls == 0 and serial.calls == 300 and choice.threads == 1


def test_forced_single_thread_keeps_one_thread():
    threads.force_single_thread(True)
    serial, parallel = Recorder("s"), Recorder("p")
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(300):
        choice()
    assert parallel.calls == 0


@pytest.mark.parametrize("value", ["0", "two", "-1", "1.5"])
def test_bad_env_value_is_named(monkeypatch, value):
    monkeypatch.setenv(threads.ENV_THREADS, value)
    with pytest.raises(ValueError, match="CLOTH_TUI_THREADS"):
        threads.env_threads()


def test_losing_parallel_kernel_is_tried_ever_more_rarely():
    # The parallel kernel takes 20 ms, the serial none: every try loses and the wait doubles.
    serial, parallel = Recorder("s"), Recorder("p", 0.02)
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(2000):
        choice()
    assert 1 <= parallel.calls <= 9  # tries after 8, 24, 56, 120, …: log2 of the calls
    assert choice.threads == 1 and choice.kernel_name == "s"


def test_a_losing_parallel_kernel_is_tried_again_within_max_wait(monkeypatch):
    # After a loss the backoff counts calls, but a quiet machine must not stay on one thread
    # for long because of one unlucky try: a try is due again after MAX_WAIT_S at the most.
    monkeypatch.setattr(threads, "MAX_WAIT_S", 0.05)
    serial, parallel = Recorder("s", 0.001), Recorder("p", 0.02)
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(12):
        choice()
    assert parallel.calls == 1  # tried after FIRST_PROBE calls and lost
    tries = parallel.calls
    end = CLOCK.perf_counter() + 0.3
    while CLOCK.perf_counter() < end:
        choice()
    assert parallel.calls - tries >= 3  # ~every 50 ms, not after 16, 32, 64… calls


def test_one_core_means_serial(monkeypatch):
    monkeypatch.setattr(threads, "usable_cores", lambda: 1)
    serial, parallel = Recorder("s"), Recorder("p")
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(100):
        choice()
    assert parallel.calls == 0


def test_winning_parallel_kernel_is_chosen_and_dropped_when_it_slows(monkeypatch):
    serial, parallel = Recorder("s", 0.01), Recorder("p")
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(40):
        choice()
    assert choice.threads == 2 and choice.kernel_name == "p"
    parallel.seconds = 0.05  # the other core got busy: barriers stall
    choice()
    assert choice.threads == 1
    before = parallel.calls
    for _ in range(10):
        choice()
    assert parallel.calls == before  # backed off


def test_a_try_is_judged_on_warm_caches_not_on_its_first_call():
    # The first parallel call after serial ones finds the data in the other core's cache and
    # is barely faster than one thread; warm, it is twice as fast. A one-call try lost on
    # that alone (the 256² sheet ran on one thread in about half the bench runs).
    last = {"kernel": "s"}

    class Serial(Recorder):
        def __call__(self, *args):
            last["kernel"] = "s"
            super().__call__()

    class ColdThenWarm(Recorder):
        def __call__(self, *args):
            self.seconds = 0.0095 if last["kernel"] == "s" else 0.005
            last["kernel"] = "p"
            super().__call__()

    serial, parallel = Serial("s", 0.01), ColdThenWarm("p")
    choice = threads.KernelChoice(serial, parallel)
    serial_calls = threads.FIRST_PROBE - 1  # the try starts on call FIRST_PROBE
    for _ in range(serial_calls + threads.PROBE_CALLS):
        choice()
    assert choice.threads == 2 and parallel.calls == threads.PROBE_CALLS
    for _ in range(30):
        choice()
    assert choice.threads == 2 and serial.calls == serial_calls


def test_a_try_that_starts_much_slower_stops_after_one_call():
    # Contention shows on the first call: the try ends there, as before PROBE_CALLS.
    serial, parallel = Recorder("s", 0.002), Recorder("p", 0.01)
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(threads.FIRST_PROBE + 3):
        choice()
    assert parallel.calls == 1 and choice.threads == 1 and serial.calls == threads.FIRST_PROBE + 2


@pytest.mark.parametrize("runnable,load", [
    # where the instant count of runnable threads is unknown (not Linux), the load average
    (None, 3.0),
    # A busy process started a moment ago has not yet moved the load average; the count of
    # runnable threads sees it at once (itself and this thread fill both cores).
    (2, 0.5)])
def test_no_parallel_try_while_the_cores_are_busy(monkeypatch, runnable, load):
    monkeypatch.setattr(threads, "runnable_now", lambda: runnable)
    monkeypatch.setattr(threads, "load_average", lambda: load)
    serial, parallel = Recorder("s", 0.002), Recorder("p")
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(40):
        choice()
    assert parallel.calls == 0


def test_a_busy_past_minute_does_not_stop_tries_while_a_core_is_idle_now(monkeypatch):
    # The load average counts this process's own parallel runs of the last minute: it must
    # not keep the parallel kernel from being tried once the cores are free again.
    monkeypatch.setattr(threads, "load_average", lambda: 2.0)
    serial, parallel = Recorder("s", 0.002), Recorder("p")
    choice = threads.KernelChoice(serial, parallel)
    for _ in range(40):
        choice()
    assert parallel.calls > 0


def test_runnable_now_counts_at_least_the_caller():
    running = threads.runnable_now()
    assert running is None or running >= 1


def test_preempted_serial_kernel_means_no_parallel_try(monkeypatch):
    # A kernel that got a fraction of its wall time on the CPU (here none: the extreme of
    # preemption) shows a machine with no idle core: the parallel kernel is not tried.
    def sleepy():
        CLOCK.spend(0.002, on_cpu=False)
    sleepy.__name__ = "s"
    parallel = Recorder("p")
    choice = threads.KernelChoice(sleepy, parallel)
    for _ in range(40):
        choice()
    assert parallel.calls == 0 and choice.contended
