"""analytic.registry.is_name: the one-file check that replaced listing the library folder on every load must
answer as membership in catalog.names() does."""

import pytest

from analytic import registry
from analytic.catalog import LIBRARY, names
from analytic._common import ParameterError


def test_every_listed_name_is_a_name():
    assert names() and all(registry.is_name(n) for n in names())


@pytest.mark.parametrize("text", ["", "nosuch", "fourbar.toml", "library", ".", "..",
                                  f"../{LIBRARY.name}/jansen", "jansen/", str(LIBRARY / "jansen")])
def test_what_is_not_listed_is_not_a_name(text):
    assert text not in names()
    assert not registry.is_name(text)


def test_an_unknown_name_still_names_the_choices():
    with pytest.raises(ParameterError, match="fourbar"):
        registry.definition("nosuch_mechanism")
