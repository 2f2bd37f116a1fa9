"""Last step before disk: an executed notebook a TA can open without running the student's code.

formgrader and ``nbgrader generate_feedback`` render ``autograded/`` with
nbconvert's HTML templates, which do not sanitize: a ``text/html``,
``application/javascript`` or ``image/svg+xml`` output, raw HTML in a markdown
cell, a raw cell, or an nbgrader ``grade_id`` in cell metadata lands in the page
as markup and runs with the TA's session (it can rewrite every grade through
formgrader's API). Every output here comes from the student's kernel, whose
display machinery the student controls, so outputs of *every* code cell are
treated alike: only plain text, stream text, error tracebacks and PNG pictures
that really are PNG files are kept. Markdown, raw cells and metadata the
instructor wrote are restored from the source notebook; the rest is made inert.
"""

from __future__ import annotations

import base64
import binascii
import copy
import html
import json
import re

import nbformat

from grader.grade_ids import grade_id
from grader.output_caps import MAX_CELL_OUTPUT_BYTES, MAX_NOTEBOOK_OUTPUT_BYTES, MAX_OUTPUTS_PER_CELL, MAX_OUTPUTS_PER_NOTEBOOK


_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# A character reference (``&lt;``, ``&#60;``, ``&#x3c;``): markdown decodes those, in link targets twice.
_CHAR_REF = re.compile(r"&(?=#[0-9]|#[xX][0-9a-fA-F]|[A-Za-z][A-Za-z0-9]*;)")
# A script URL scheme, also written ``javascript\:`` (a markdown backslash escape); nbconvert keeps such links.
_SCRIPT_SCHEME = re.compile(r"\b((?:java|vb|live)script)(?=[ \t]*\\?:)", re.IGNORECASE)
_ATTACHMENT_NAME = re.compile(r"[A-Za-z0-9._-]{1,100}")


def _text(value) -> str | None:
    """A notebook text field (a string, or a list of strings nbformat joins); None if it is neither."""
    if isinstance(value, str):
        return value
    if isinstance(value, list) and all(isinstance(v, str) for v in value):
        return "".join(value)
    return None


def _png(value) -> str | None:
    """``value`` as clean base64 if it decodes to a PNG file, else None."""
    text = _text(value)
    if text is None:
        return None
    compact = "".join(text.split())
    try:
        data = base64.b64decode(compact, validate=True)
    except (binascii.Error, ValueError):
        return None
    if not (data.startswith(_PNG_SIGNATURE) and data[12:16] == b"IHDR"):
        return None
    return compact


def _safe_output(out) -> tuple[dict | None, list[str]]:
    """One output reduced to inert content, and the kinds of content removed from it."""
    kind = out.get("output_type") if isinstance(out, dict) else None
    if kind == "stream":
        text = _text(out.get("text"))
        if text is None:
            return None, ["a malformed stream output"]
        name = out.get("name") if out.get("name") in ("stdout", "stderr") else "stdout"
        return nbformat.v4.new_output("stream", name=name, text=text), []
    if kind == "error":
        trace = out.get("traceback")
        lines = [t for t in trace if isinstance(t, str)] if isinstance(trace, list) else []
        return nbformat.v4.new_output(
            "error", ename=str(out.get("ename", "")), evalue=str(out.get("evalue", "")), traceback=lines
        ), []
    if kind not in ("display_data", "execute_result"):
        return None, [f"a {str(kind)[:40]!r} output"]
    data = out.get("data") if isinstance(out.get("data"), dict) else {}
    kept, removed = {}, []
    for mime, value in data.items():
        if mime == "text/plain" and _text(value) is not None:
            kept[mime] = _text(value)
        elif mime == "image/png" and _png(value) is not None:
            kept[mime] = _png(value)
        else:
            removed.append(str(mime)[:80] if mime != "image/png" else "image/png that is not a PNG file")
    if removed:
        note = f"[the grader removed this output's {', '.join(removed)}]"
        kept["text/plain"] = f"{kept['text/plain']}\n{note}" if "text/plain" in kept else note
    safe = nbformat.v4.new_output(kind, data=kept)  # metadata (sizes, filenames, isolation) is dropped
    if kind == "execute_result":
        count = out.get("execution_count")
        safe["execution_count"] = count if isinstance(count, int) and not isinstance(count, bool) else None
    return safe, removed


def _inert_markdown(text: str, attached: set[str]) -> str:
    """Markdown that renders as the same words, with no HTML and no script links.

    Every ``<`` becomes ``&lt;`` (no tag, comment or autolink can start); an ``&``
    that starts a character reference becomes a full-width ``＆`` (mistune decodes
    link targets twice, so ``&amp;#58;`` would still spell a ``:``; no escaping
    survives that, a different character does); ``javascript:``-like schemes,
    also written ``javascript\\:``, are renamed ``…-blocked:``; and
    ``attachment:`` references to anything but ``attached`` become
    ``attachment-removed:``. ``>`` is kept: it cannot open markup, and it is
    markdown's quote marker.
    """
    text = _CHAR_REF.sub("\uff06", text)
    text = text.replace("<", "&lt;")
    text = _SCRIPT_SCHEME.sub(r"\1-blocked", text)
    # nbconvert fails the whole page on an image ``attachment:NAME`` whose NAME is not attached. Only a kept
    # name that ends the link target is left alone; the rename consumes no name, so nested references count too.
    kept = "|".join(re.escape(name) for name in sorted(attached))
    unknown = r"attachment(\\?:)" + (rf"(?!(?:{kept})(?:[\s)]|\Z))" if kept else "")
    return re.sub(unknown, r"attachment-removed\1", text)


def _png_attachments(value) -> dict:
    """The attachments that are PNG files with plain names, as ``{name: {"image/png": base64}}``."""
    kept = {}
    for name, bundle in (value.items() if isinstance(value, dict) else ()):
        png = _png(bundle.get("image/png")) if isinstance(bundle, dict) else None
        if png is not None and isinstance(name, str) and _ATTACHMENT_NAME.fullmatch(name):
            kept[name] = {"image/png": png}
    return kept


def neutralize(nb: nbformat.NotebookNode, source: nbformat.NotebookNode) -> list[str]:
    """Make an executed notebook inert for formgrader and feedback pages, in place.

    Parameters
    ----------
    nb : NotebookNode
        The executed, sanitized submission (modified in place).
    source : NotebookNode
        The instructor notebook it was graded against: its metadata, its cells'
        metadata (matched by ``grade_id``) and its markdown and raw cells (matched
        by text) are trusted.

    Returns
    -------
    list of str
        What was removed or rewritten, one line each, e.g. ``"cell 3: removed
        text/html, application/javascript"``.

    Notes
    -----
    Code cells keep only ``stream`` and ``error`` outputs and the ``text/plain``
    and valid ``image/png`` parts of display outputs, no output metadata, and
    only their first outputs within :data:`MAX_OUTPUTS_PER_CELL` outputs and
    :data:`MAX_CELL_OUTPUT_BYTES` per cell and :data:`MAX_OUTPUTS_PER_NOTEBOOK`
    outputs and :data:`MAX_NOTEBOOK_OUTPUT_BYTES` in all (a line says how many
    were dropped). A cell's metadata becomes its source
    cell's (points, grade ids, locks), or nothing. Markdown and raw cells that are
    not the instructor's text are escaped; their attachments keep only PNG pictures. Notebook
    metadata (and so any widget state) is the source's.
    """
    notes: list[str] = []
    by_gid = {grade_id(c): c for c in source.cells if grade_id(c)}
    trusted_text = {(c.cell_type, c.source): c for c in source.cells if c.cell_type in ("markdown", "raw")}
    nb.metadata = copy.deepcopy(source.metadata)
    nb.metadata.pop("widgets", None)
    total_outputs = total_bytes = 0
    restored: set[str] = set()
    for index, cell in enumerate(nb.cells):
        where = f"cell {index + 1}"
        gid = grade_id(cell)
        original = by_gid.get(gid)
        if original is not None and original.cell_type == cell.cell_type and gid not in restored:
            restored.add(gid)
            cell.metadata = copy.deepcopy(original.metadata)
        else:
            if gid is not None:
                notes.append(f"{where}: dropped nbgrader metadata naming an unknown cell")
            cell.metadata = nbformat.NotebookNode()
        if cell.cell_type in ("markdown", "raw"):
            text = _text(cell.get("source")) or ""
            trusted = trusted_text.get((cell.cell_type, text))
            attachments = cell.pop("attachments", None)
            if trusted is not None:
                if trusted.get("attachments"):
                    cell["attachments"] = copy.deepcopy(trusted.attachments)
                continue
            kept = _png_attachments(attachments) if cell.cell_type == "markdown" else {}
            if kept:
                cell["attachments"] = kept
            if attachments and len(kept) < (len(attachments) if isinstance(attachments, dict) else 1):
                notes.append(f"{where}: dropped attachments that are not PNG pictures")
            # nbconvert renders markdown without sanitizing, and raw cells verbatim.
            inert = _inert_markdown(text, set(kept)) if cell.cell_type == "markdown" else html.escape(text, quote=False)
            if inert != text:
                notes.append(f"{where}: escaped the HTML in a {cell.cell_type} cell")
            cell.source = inert
            continue
        if cell.cell_type != "code":
            continue
        count = cell.get("execution_count")
        cell["execution_count"] = count if isinstance(count, int) and not isinstance(count, bool) else None
        outputs, cell_bytes, removed, dropped = [], 0, [], 0
        for out in cell.get("outputs", []):
            if dropped:  # the cell keeps a prefix of its outputs; the rest are not even looked at
                dropped += 1
                continue
            safe, gone = _safe_output(out)
            removed += gone
            if safe is None:
                continue
            size = len(json.dumps(safe))
            if (
                len(outputs) >= MAX_OUTPUTS_PER_CELL
                or total_outputs >= MAX_OUTPUTS_PER_NOTEBOOK
                or cell_bytes + size > MAX_CELL_OUTPUT_BYTES
                or total_bytes + size > MAX_NOTEBOOK_OUTPUT_BYTES
            ):
                dropped += 1
                continue
            outputs.append(safe)
            cell_bytes, total_bytes, total_outputs = cell_bytes + size, total_bytes + size, total_outputs + 1
        if dropped:
            outputs.append(nbformat.v4.new_output(
                "stream", name="stderr",
                text=f"[the grader dropped {dropped} more output(s) of this cell: at most {MAX_OUTPUTS_PER_CELL} "
                     f"outputs and {MAX_CELL_OUTPUT_BYTES // 2**20} MiB per cell, {MAX_OUTPUTS_PER_NOTEBOOK} outputs "
                     f"and {MAX_NOTEBOOK_OUTPUT_BYTES // 2**20} MiB per notebook are kept]\n",
            ))
            notes.append(f"{where}: dropped {dropped} output(s) over the limits")
        if removed:
            notes.append(f"{where}: removed {', '.join(sorted(set(removed)))}")
        cell.outputs = outputs
        cell.pop("attachments", None)
    return notes
