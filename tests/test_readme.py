"""The numbers the README quotes are the numbers the code computes: its first result
(the default run on Table 1) is recomputed in-process and compared line by line."""

from __future__ import annotations

import re

from conftest import ROOT


def _quoted_block() -> list[str]:
    text = (ROOT / "README.md").read_text()
    block = re.search(r"```\n(table1 \(balanced preset\).*?)```", text, re.S)
    assert block, "the README's first result is not where this test looks for it"
    return block.group(1).splitlines()


def test_the_readmes_first_result_is_what_the_default_run_computes():
    import wheel_squeal as ws
    from wheel_squeal.present.text import verdict_lines

    a = ws.analyse(ws.load_design(), remedy=False)
    quoted = _quoted_block()
    verdict = next(line for line in quoted if line.startswith("VERDICT:"))
    assert verdict_lines(a.verdict)[0] == verdict
    why = next(line for line in quoted if line.strip().startswith("why:"))
    assert why.strip() in [line.strip() for line in verdict_lines(a.verdict)]
