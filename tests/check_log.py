"""The checks of a Python test script: each printed as it is made, counted for the exit status.

    from check_log import check, summary
    check(condition, "what is checked", "detail shown when it fails")
    sys.exit(summary())
"""

passed = 0
failed = 0


def check(condition, what, detail=""):
    global passed, failed
    if condition:
        passed += 1
        print("ok      " + what, flush=True)
    else:
        failed += 1
        print("FAILED  " + what + (": " + detail if detail else ""), flush=True)
    return condition


def summary():
    """Prints the counts; the exit status: 1 when a check failed."""
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0
