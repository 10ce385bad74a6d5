#!/usr/bin/env python3
"""Checks that every relative link and image in README.md and docs/**/*.md points to an existing file,
and that every #anchor names a heading of its target (GitHub slugs, simplified).
Usage: python3 docs/check_links.py [project root]   (exit 1 on any broken link)"""
import glob, os, re, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
os.chdir(root)
files = ['README.md'] + sorted(glob.glob('docs/*.md')) + sorted(glob.glob('docs/*/*.md'))
link = re.compile(r'!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+"[^"]*")?\)')
def slug(h):
    h = h.strip().lower()
    h = re.sub(r'[^\w\- ]', '', h)   # drop punctuation (keeps unicode letters/digits, _ and -)
    return h.replace(' ', '-')
def anchors(path):
    out = set(); inside = False
    for l in open(path, encoding='utf-8'):
        if l.startswith('```'): inside = not inside
        if not inside and l.startswith('#'):
            out.add(slug(l.lstrip('#')))
    return out
bad = 0; n = 0
for f in files:
    text = open(f, encoding='utf-8').read()
    text = re.sub(r'```.*?```', '', text, flags=re.S)   # no links inside code blocks
    for m in link.finditer(text):
        url = m.group(1)
        if re.match(r'^[a-z]+:', url): continue      # http:, https:, mailto:
        n += 1
        path, _, frag = url.partition('#')
        target = os.path.normpath(os.path.join(os.path.dirname(f), path)) if path else f
        if not os.path.exists(target):
            print(f'{f}: {url}: no such file ({target})'); bad += 1; continue
        if frag and target.endswith('.md') and frag not in anchors(target):
            print(f'{f}: {url}: no heading #{frag} in {target}'); bad += 1
print(f'{n} relative links checked in {len(files)} files, {bad} broken')
sys.exit(1 if bad else 0)
