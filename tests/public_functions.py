#!/usr/bin/env python3
"""The functions the public headers declare, checked against what the shared library exports.

Usage: public_functions.py INCLUDE_DIR SYMBOLS_FILE
SYMBOLS_FILE holds `nm -D --defined-only LIB | c++filt` output. Every function a header under
INCLUDE_DIR declares without defining it (C functions by name; C++ free functions, constructors,
destructors, operators and public members by qualified name, each overload counted) must be
exported; a header that forgets its visibility block fails here instead of at a user's link.
Functions defined in the header (inline, templates, = default / = delete) need no symbol.
"""
import pathlib
import re
import sys

SCOPE_KEYWORDS = re.compile(r'^(?:template\s*<.*>\s*)?(namespace|class|struct|union|enum)\b(.*)$', re.S)
KEYWORDS = {'if', 'for', 'while', 'switch', 'return', 'sizeof', 'static_assert', 'decltype', 'alignas',
            'noexcept', 'void', 'int', 'char', 'double', 'float', 'bool', 'unsigned', 'long', 'short'}


def strip(text):
    """The header without comments, string literals' contents and preprocessor lines."""
    text = re.sub(r'/\*.*?\*/', ' ', text, flags=re.S)
    text = re.sub(r'//[^\n]*', '', text)
    text = re.sub(r'"(?:\\.|[^"\\])*"', '""', text)
    text = re.sub(r"'(?:\\.|[^'\\])*'", "''", text)
    lines, out, continued = text.split('\n'), [], False
    for line in lines:
        directive = continued or line.lstrip().startswith('#')
        continued = directive and line.rstrip().endswith('\\')
        out.append('' if directive else line)
    return '\n'.join(out)


def matching(text, i):
    """Index just past the bracket that closes the one at text[i]."""
    depth = 0
    pairs = {'{': '}', '(': ')'}
    open_, close = text[i], pairs[text[i]]
    for j in range(i, len(text)):
        if text[j] == open_:
            depth += 1
        elif text[j] == close:
            depth -= 1
            if depth == 0:
                return j + 1
    raise ValueError('unbalanced brackets')


def function_name(statement):
    """The declared function's name ('render', '~Renderer', 'operator=') or None."""
    s = ' '.join(statement.split())
    s = re.sub(r'^(?:(?:public|private|protected)\s*:\s*)+', '', s)
    if not s or re.match(r'^(typedef|using|friend|template|static_assert|inline|constexpr)\b', s):
        return None
    op = re.search(r'\boperator\s*(\(\)|\[\]|[^\w\s(]+|\s[\w:<>&*\s]+?)\s*\(', s)
    if op:
        if '=' in s[:op.start()]:
            return None
        paren = op.end() - 1
        name = 'operator' + (' ' if op.group(1).startswith(' ') else '') + op.group(1).strip()
    else:
        paren = s.find('(')
        if paren < 0 or '=' in s[:paren]:
            return None
        if s[paren + 1:].lstrip().startswith(('*', '&', '^')):  # a function pointer variable
            return None
        if s[:paren].count('<') > s[:paren].count('>'):  # a member like std::function<Status(int)> f
            return None
        m = re.search(r'(~?[A-Za-z_]\w*)\s*$', s[:paren])
        if not m or m.group(1) in KEYWORDS or re.fullmatch(r'[A-Z][A-Z0-9]*_[A-Z0-9_]*', m.group(1)):  # a macro
            return None
        name = m.group(1)
    # A declaration ends with its parameter list and qualifiers; `= 0`, `= default` and
    # `= delete` need no symbol.
    tail = s[matching(s, paren):]
    if re.search(r'=\s*(0|default|delete)\s*$', tail):
        return None
    return name


def declarations(text):
    """(qualified name, is_c) for each function declared without a body in `text`."""
    text = strip(text)
    found = []
    scopes = []  # (kind, name, public) for namespace / class / struct / extern "C"
    statement = ''
    i = 0
    while i < len(text):
        c = text[i]
        if c == '(':
            j = matching(text, i)
            statement += text[i:j]
            i = j
            continue
        if c == ';':
            name = function_name(statement)
            in_class = any(k in ('class', 'struct') for k, _, _ in scopes)
            public = all(p for _, _, p in scopes)
            at_namespace = not in_class
            if name and public and not (at_namespace and re.match(r'\s*static\b', statement)):
                names = [n for k, n, _ in scopes if k != 'extern' and n]
                is_c = any(k == 'extern' for k, _, _ in scopes) and not names
                found.append(('::'.join(names + [name]), is_c))
            statement = ''
            i += 1
            continue
        if c == '{':
            head = ' '.join(statement.split())
            head = re.sub(r'^(?:(?:public|private|protected)\s*:\s*)+', '', head)
            m = SCOPE_KEYWORDS.match(head)
            if head.startswith('extern ""'):
                scopes.append(('extern', '', True))
                statement = ''
                i += 1
                continue
            if m and m.group(1) == 'namespace':
                scopes.append(('namespace', m.group(2).strip(), True))
                statement = ''
                i += 1
                continue
            if m and m.group(1) in ('class', 'struct', 'union') and '(' not in head and '=' not in head:
                words = re.findall(r'[A-Za-z_]\w*', m.group(2).split(':')[0])
                words = [w for w in words if w not in ('final', 'alignas')]
                templated = head.startswith('template')
                scopes.append((m.group(1), words[-1] if words else '', m.group(1) != 'class' and not templated))
                statement = ''
                i += 1
                continue
            # An enum's list, a function body or a braced initializer: nothing declared inside.
            j = matching(text, i)
            if '(' in head and not (m and m.group(1) == 'enum'):
                statement = ''  # a function defined here: no symbol needed
            else:
                statement += ' {} '
            i = j
            continue
        if c == '}':
            scopes.pop()
            statement = ''
            i += 1
            continue
        if c == ':' and scopes and scopes[-1][0] in ('class', 'struct'):
            m = re.search(r'\b(public|private|protected)\s*$', statement)
            if m and text[i + 1:i + 2] != ':':
                kind, name, _ = scopes[-1]
                scopes[-1] = (kind, name, m.group(1) == 'public')
                statement = ''
                i += 1
                continue
        statement += c
        i += 1
    return found


def main():
    include_dir, symbols_file = pathlib.Path(sys.argv[1]), sys.argv[2]
    exported = set()
    for line in pathlib.Path(symbols_file).read_text().splitlines():
        parts = line.split(None, 2)
        if len(parts) == 3 and parts[1] in 'TtWiu':
            exported.add(re.sub(r'\[abi:\w+\]', '', parts[2]))  # scene_to_json[abi:cxx11](...)
    fail = False
    total_c = total_cpp = 0
    for header in sorted(include_dir.rglob('*.h*')):
        counts = {}
        for name, is_c in declarations(header.read_text()):
            counts[(name, is_c)] = counts.get((name, is_c), 0) + 1
        for (name, is_c), n in sorted(counts.items()):
            if is_c:
                total_c += 1
                have = 1 if name in exported else 0
            else:
                total_cpp += n
                have = len({s for s in exported if s.startswith(name + '(')})
            if have < n:
                print(f'declared in {header.name}, not exported: {name}' +
                      (f' ({n} overloads declared, {have} exported)' if n > 1 else ''), file=sys.stderr)
                fail = True
    # A parser that stopped finding declarations would pass vacuously.
    if total_c < 40 or total_cpp < 40:
        print(f'could not read the declarations of {include_dir}: {total_c} C, {total_cpp} C++ functions',
              file=sys.stderr)
        fail = True
    print(f'declared functions exported: {total_c} C, {total_cpp} C++')
    return 1 if fail else 0


if __name__ == '__main__':
    sys.exit(main())
