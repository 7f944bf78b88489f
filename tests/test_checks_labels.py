"""Each check kind owns its words: the report and the terminal read them from the kind, never from a table of
output keys kept beside it (issue 22)."""

from camdyn.design.checks import CheckKind


def test_every_check_kind_says_what_it_judges():
    for kind in CheckKind:
        assert kind.label and kind.label != kind.value, kind
