"""Shared by the pvpython tests (imported from the script's own folder): checks that record their
failures, the end of a test, and the Summary table as a dict.

    from brt_checks import check, finish, messages, output_text, summary_rows, table_rows
"""
import sys

failures = []
verbose = True  # False: print failures only (tests with thousands of checks)


def check(cond, what):
    """Records `what` as a failure unless cond holds; prints the outcome."""
    if verbose or not cond:
        print(("  ok   " if cond else "  FAIL ") + what)
    if not cond:
        failures.append(what)


def finish(passed=None):
    """Exits 1 with the count when any check failed, else prints `passed` (if given) and exits 0."""
    if failures:
        print("%d failures" % len(failures))
        sys.exit(1)
    if passed:
        print(passed)
    sys.exit(0)


def table_rows(table):
    """A Quantity / Value table (the filter's Summary, port 3) as {quantity: value}."""
    return {table.GetValue(r, 0).ToString(): table.GetValue(r, 1).ToDouble()
            for r in range(table.GetNumberOfRows())}


def summary_rows(filt):
    """The Summary port of a B-Rep Thickness proxy as {quantity: value}."""
    from paraview import servermanager as sm
    return table_rows(sm.Fetch(filt, idx=3))


def messages(proxy, event="WarningEvent"):
    """A list that collects the text of every `event` (WarningEvent, ErrorEvent) the proxy's
    algorithm emits from now on."""
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING
    got = []

    @calldata_type(VTK_STRING)
    def on_message(obj, ev, message):
        got.append(message)

    proxy.GetClientSideObject().AddObserver(event, on_message)
    return got


def output_text(run):
    """The text that ParaView's Output Messages would show while run() runs (vtkOutputWindow: the
    filter's summary message among them). pvpython prints through the same window, so nothing is
    printed in between."""
    from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
    previous = vtkOutputWindow.GetInstance()
    window = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(window)
    try:
        run()
    finally:
        vtkOutputWindow.SetInstance(previous)
    return window.GetOutput()
