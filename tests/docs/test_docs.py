#!/usr/bin/env python3
"""The documentation holds together: every relative link of README.md and docs/*.md reaches a file
(and a heading, for a #fragment, by GitHub's rules for heading anchors); every code block marked
`<!-- quoted from examples/NAME -->` is that file verbatim, so the code a reader copies is the code
CI builds and runs; every program in examples/ is referred to by a page; and no sentence stands on
two pages (each fact has one home). Run by ctest; standalone: python3 tests/docs/test_docs.py."""
import glob
import os
import re
import tempfile
import unittest

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

LINK = re.compile(r'(?<!!)\[[^\]]*\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)')
QUOTE = re.compile(r'<!-- quoted from (examples/[^ ]+) -->\s*\n```[a-z+]*\n(.*?)```', re.S)


def pages():
    return [os.path.join(SOURCE, 'README.md')] + sorted(glob.glob(os.path.join(SOURCE, 'docs', '*.md')))


def read(path):
    with open(path, encoding='utf-8') as handle:
        return handle.read()


def without_code(text):
    """The text outside fenced code blocks and inline code spans."""
    text = re.sub(r'```.*?```', '', text, flags=re.S)
    return re.sub(r'`[^`\n]*`', '', text)


def anchors(path):
    """GitHub's heading anchors: lower case, punctuation other than '-' and '_' dropped, spaces to
    '-', repeats numbered -1, -2, ..."""
    seen = {}
    result = set()
    for line in re.sub(r'```.*?```', '', read(path), flags=re.S).splitlines():
        match = re.match(r'#{1,6}\s+(.*?)\s*#*\s*$', line)
        if not match:
            continue
        slug = re.sub(r'[^\w\- ]', '', match.group(1).strip().lower()).replace(' ', '-')
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        result.add(slug if count == 0 else '%s-%d' % (slug, count))
    return result


def sentences(text):
    """Sentences of eight words or more, with their whitespace folded and markup dropped."""
    text = re.sub(r'^\s*\|.*$', '', without_code(text), flags=re.M)  # table rows: figures, not prose
    text = re.sub(r'[*_>#]', '', re.sub(r'\]\([^)]*\)', ']', text))
    for piece in re.split(r'(?<=[.!?])\s+|\n\s*\n|\n\s*[-0-9.]+\s', text):
        words = piece.split()
        if len(words) >= 8:
            yield ' '.join(words)


class Documentation(unittest.TestCase):
    def test_every_relative_link_reaches_a_file_and_heading(self):
        broken = []
        for page in pages():
            for match in LINK.finditer(without_code(read(page))):
                target = match.group(1) or match.group(2)
                if re.match(r'[a-z]+:', target):
                    continue  # http:, https:, mailto:
                path, _, fragment = target.partition('#')
                resolved = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
                where = os.path.relpath(page, SOURCE)
                if not os.path.exists(resolved):
                    broken.append('%s: %s (no such file)' % (where, target))
                elif fragment and resolved.endswith('.md') and fragment not in anchors(resolved):
                    broken.append('%s: %s (no such heading)' % (where, target))
        self.assertEqual(broken, [])

    def test_quoted_examples_are_the_files_verbatim(self):
        quoted = 0
        for page in pages():
            for match in QUOTE.finditer(read(page)):
                quoted += 1
                example = os.path.join(SOURCE, match.group(1))
                self.assertTrue(os.path.exists(example), match.group(1))
                self.assertEqual(match.group(2), read(example),
                                 '%s quotes %s, which has changed' % (os.path.relpath(page, SOURCE), match.group(1)))
        self.assertGreater(quoted, 0, 'the README quotes no example')

    def test_every_example_is_referred_to_by_a_page(self):
        text = ''.join(read(page) for page in pages())
        examples = sorted(glob.glob(os.path.join(SOURCE, 'examples', '*.cpp')))
        self.assertTrue(examples)
        for example in examples:
            self.assertIn('examples/' + os.path.basename(example), text)

    def test_no_sentence_stands_on_two_pages(self):
        home = {}
        repeated = []
        for page in pages():
            for sentence in set(sentences(read(page))):
                if sentence in home:
                    repeated.append('%s and %s: "%s"' % (home[sentence], os.path.relpath(page, SOURCE), sentence))
                else:
                    home[sentence] = os.path.relpath(page, SOURCE)
        self.assertEqual(repeated, [])

    def test_the_checks_find_what_they_look_for(self):
        # GitHub's anchors of hand-made headings, and a sentence counted only when long enough.
        with tempfile.NamedTemporaryFile('w', suffix='.md', delete=False) as page:
            page.write('# The C++ API, in ten lines\n\n## Exit codes\n\n## Exit codes\n'
                       '```sh\n# not a heading\n```\n')
        try:
            self.assertEqual(anchors(page.name), {'the-c-api-in-ten-lines', 'exit-codes', 'exit-codes-1'})
        finally:
            os.unlink(page.name)
        found = list(sentences('A sentence that is long enough to be counted here. Short one.'))
        self.assertEqual(found, ['A sentence that is long enough to be counted here.'])

if __name__ == '__main__':
    unittest.main()
