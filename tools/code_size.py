#!/usr/bin/env python3
"""Sizes of the library and tool sources: files over 700 lines and functions over 120 (docs/architecture.md).

A heuristic brace counter: comments and string literals are blanked, and a `{` at namespace or class depth
whose preceding text ends like a function signature opens a function; its length runs to the matching `}`.
Exits 1 when something is over a limit.

  python3 tools/code_size.py [--function-lines N] [--file-lines N] [FILE...]
"""
import re, sys, os
def strip(src):
    # remove comments and string/char literals, keep newlines
    out=[];i=0;n=len(src)
    while i<n:
        c=src[i]
        if src.startswith('//',i):
            j=src.find('\n',i); j=n if j<0 else j; i=j; continue
        if src.startswith('/*',i):
            j=src.find('*/',i+2); j=n if j<0 else j+2; out.append('\n'*src.count('\n',i,j)); i=j; continue
        if src.startswith('R"',i):
            m=re.match(r'R"([^(]*)\(',src[i:])
            if m:
                end=')'+m.group(1)+'"'; j=src.find(end,i); j=n if j<0 else j+len(end)
                out.append('""'+'\n'*src.count('\n',i,j)); i=j; continue
        if c=='"' or c=="'":
            j=i+1
            while j<n and src[j]!=c:
                if src[j]=='\\': j+=1
                j+=1
            out.append(c+c); i=j+1; continue
        out.append(c); i+=1
    return ''.join(out)
def funcs(path):
    src=strip(open(path,errors='replace').read())
    res=[]; stack=[]  # each: (kind, start_line, name)
    line=1; last=0
    for i,c in enumerate(src):
        if c=='\n': line+=1
        elif c=='{':
            head=src[last:i]
            h=' '.join(head.split())
            infunc=any(k=='f' for k,_,_ in stack)
            if infunc: kind='b'
            elif re.search(r'\b(namespace|struct|class|union|enum)\b[^;()]*$',h) or h.endswith('=') or re.search(r'(=|\[\]|return)\s*$',h) or not h:
                kind='c'
            elif re.search(r'\)\s*(const|noexcept|override|final|mutable|->\s*[\w:<>,\s&*]+|\s)*$',h) or re.search(r'\)\s*:\s*.*$',h):
                m=re.search(r'([\w:~<>]+(?:operator\S*)?)\s*\(',h)
                kind='f'; 
                stack.append((kind,line,m.group(1) if m else h[-40:])); last=i+1; continue
            else: kind='c'
            stack.append((kind,line,None)); last=i+1
        elif c=='}':
            if stack:
                k,s,nm=stack.pop()
                if k=='f': res.append((line-s+1,s,nm))
            last=i+1
        elif c==';': last=i+1
    return res
def library_sources(root):
    """The library and tool sources: tracked .cpp and .hpp files outside tests/ and bench/."""
    import subprocess
    out = subprocess.run(["git", "-C", root, "ls-files", "*.cpp", "*.hpp"], capture_output=True, text=True,
                         check=True).stdout.split()
    return [os.path.join(root, p) for p in out if not p.startswith(("tests/", "bench/"))]


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--function-lines", type=int, default=120)
    ap.add_argument("--file-lines", type=int, default=700)
    ap.add_argument("files", nargs="*", help="default: the library and tool sources")
    a = ap.parse_args()
    files = a.files or library_sources(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    over = 0
    for p in files:
        n = open(p, errors="replace").read().count("\n")
        if n > a.file_lines:
            print(f"{p}: {n} lines, over {a.file_lines}")
            over += 1
        for length, line, name in funcs(p):
            if length > a.function_lines:
                print(f"{p}:{line}: {name} is {length} lines, over {a.function_lines}")
                over += 1
    sys.exit(1 if over else 0)


if __name__ == "__main__":
    main()
