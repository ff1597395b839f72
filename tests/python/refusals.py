"""What the Python tests hold every refusal to (test_bad_inputs.py,
test_rules.py): the module's own words, naming the function first, without
pybind11's, C++'s or Python's own text."""
import pytest


# pybind11's, C++'s and Python's own words, which no refusal may show.
FOREIGN = ("incompatible function arguments", "Invoked with", "Unable to cast",
           "unsupported operand", "NoneType", "not supported between",
           "object cannot be interpreted", "PYBIND11", "could not convert",
           "must be real number", "std::", "_M_", "bad_alloc", "got an unexpected keyword")


def foreign(text):
    return [f for f in FOREIGN if f in text]


def refusal(call, kind, *words):
    """The exception `call()` raises: of `kind`, in the module's words (the
    first of `words`, the function, starts the message; the others are in
    it), without pybind11's, C++'s or Python's own text."""
    with pytest.raises(kind) as info:
        call()
    text = str(info.value)
    assert text.startswith(words[0] + ":"), text
    for word in words[1:]:
        assert word in text, (word, text)
    assert not foreign(text), text
    return text
