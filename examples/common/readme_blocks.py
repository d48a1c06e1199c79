"""The generated blocks of an example's README: the text between "<!-- BEGIN GENERATED: name -->"
and "<!-- END GENERATED: name -->" is replaced by what a study's report.py computes from its
result files, so that no number in a README is copied by hand."""
import re


def render(text, blocks, readme="README.md"):
    """`text` with every named block's body replaced; a block the README lacks is an error."""
    for name, body in blocks.items():
        pat = re.compile(r"(<!-- BEGIN GENERATED: %s -->\n).*?(<!-- END GENERATED: %s -->)" % (re.escape(name), re.escape(name)),
                         re.S)
        if not pat.search(text):
            raise SystemExit(f"report.py: {readme} has no block '{name}'")
        text = pat.sub(lambda m: m.group(1) + body + m.group(2), text)
    return text
