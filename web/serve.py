#!/usr/bin/python3
"""Serve the lab on 127.0.0.1: web/ at /, the WebAssembly build at /build/, models/ at /models/,
Debian's three.js and KaTeX (libjs-three, libjs-katex) at /vendor/three/ and /vendor/katex/.

    web/serve.py [--port N] [--build DIR]      (port 0, the default: a free port)

Prints the page's URL on its first line, then serves until interrupted. The browser tests
import `start()` to run the same server on a free port in a thread and stop it afterwards.
"""
import argparse
import functools
import http.server
import os
import sys
import threading

WEB = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(WEB)
# the page's libraries, as Debian installs them (scripts/setup.sh): never fetched from the network
VENDOR = {'three': '/usr/share/javascript/three', 'katex': '/usr/share/javascript/katex'}


class Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = dict(http.server.SimpleHTTPRequestHandler.extensions_map,
                          **{'.wasm': 'application/wasm', '.js': 'text/javascript',
                             '.json': 'application/json', '.xml': 'application/xml',
                             '.css': 'text/css', '.woff2': 'font/woff2', '.woff': 'font/woff',
                             '.ttf': 'font/ttf'})

    def __init__(self, *args, build_dir, **kwargs):
        self.build_dir = build_dir
        super().__init__(*args, directory=WEB, **kwargs)

    def translate_path(self, path):
        # /build/... -> the WebAssembly build, /models/... -> the repository's models,
        # /vendor/NAME/... -> Debian's copy of the library NAME
        clean = path.split('?', 1)[0].split('#', 1)[0]
        places = [('/build/', self.build_dir), ('/models/', os.path.join(ROOT, 'models'))]
        places += [('/vendor/%s/' % name, directory) for name, directory in VENDOR.items()]
        for prefix, directory in places:
            if clean.startswith(prefix):
                rest = clean[len(prefix):]
                if '..' in rest.split('/'):
                    return os.path.join(WEB, '__refused__')
                return os.path.join(directory, *rest.split('/'))
        return super().translate_path(path)

    def end_headers(self):
        self.send_header('Cache-Control', 'no-store')
        super().end_headers()

    def log_message(self, format, *args):  # quiet: the tests print what matters
        pass


def start(port=0, build_dir=None):
    """Start the server in a thread; returns (server, url). server.shutdown() stops it."""
    build_dir = build_dir or os.path.join(ROOT, 'build-web', 'web', 'wasm')
    handler = functools.partial(Handler, build_dir=os.path.abspath(build_dir))
    server = http.server.ThreadingHTTPServer(('127.0.0.1', port), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    return server, 'http://127.0.0.1:%d/' % server.server_address[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--port', type=int, default=0)
    parser.add_argument('--build', default=None, help='folder with lever_wasm.js and .wasm')
    args = parser.parse_args()
    build_dir = args.build or os.path.join(ROOT, 'build-web', 'web', 'wasm')
    if not os.path.exists(os.path.join(build_dir, 'lever_wasm.wasm')):
        sys.exit('serve.py: no lever_wasm.wasm in %s (run `make web` first)' % build_dir)
    for name, directory in VENDOR.items():
        if not os.path.isdir(directory):
            sys.exit('serve.py: no %s in %s (run scripts/setup.sh: it installs libjs-%s)'
                     % (name, directory, name))
    server, url = start(args.port, build_dir)
    print(url + '?spec=specs/5.1-lab.json', flush=True)
    print(url + '?spec=specs/5.1-check.json', flush=True)
    print(url + '?spec=specs/5.2-lab.json', flush=True)
    print(url + '?spec=specs/5.3-lab.json', flush=True)
    try:
        threading.Event().wait()
    except KeyboardInterrupt:
        server.shutdown()


if __name__ == '__main__':
    main()
