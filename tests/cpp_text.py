"""C++ source text for the source checks (tests/check_*.py): comments and
string and character literals blanked, so that what a check looks for (a
number, a brace) is code."""


def blank(text):
    """The C++ text with comments and string/char literals (raw strings too)
    blanked; every newline is kept, so line numbers hold."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            seg = text[i:(n if j < 0 else j + 2)]
            out.append("\n" * seg.count("\n"))
            i = n if j < 0 else j + 2
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            k = text.find("(", i)  # a raw string: R"delim( ... )delim"
            end = text.find(")" + text[i + 2:k] + '"', k)
            end = n if end < 0 or k < 0 else end + len(text[i + 2:k]) + 2
            out.append(" " + "\n" * text[i:end].count("\n"))
            i = end
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(" " + "\n" * text[i:j].count("\n"))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)
