"""The peer of `contphy-eval bench llm`: the same chat-completion requests against the same
loopback mock, sent by CPython's standard library (a thread pool, one keep-alive
http.client connection per thread), as a Python harness without extra packages would.

Input (stdin, JSON): {"url": "http://127.0.0.1:PORT/v1", "latency_ms": 50,
"levels": [[jobs, requests], ...]}. Output (stdout, JSON): one entry per level with
requests, failures, elapsed_ms, requests_per_second, ideal_requests_per_second and
fraction_of_ideal, like the Rust client's throughput points.
"""

import http.client
import json
import sys
import threading
import time
import urllib.parse
from concurrent.futures import ThreadPoolExecutor

BODY = json.dumps(
    {
        "model": "mock-model",
        "messages": [{"role": "user", "content": "Write a program that answers yes."}],
    }
).encode()


def main():
    request = json.load(sys.stdin)
    url = urllib.parse.urlsplit(request["url"])
    path = url.path.rstrip("/") + "/chat/completions"
    latency = request["latency_ms"] / 1000.0
    local = threading.local()

    def one(_):
        connection = getattr(local, "connection", None)
        if connection is None:
            connection = http.client.HTTPConnection(url.hostname, url.port, timeout=60)
            local.connection = connection
        try:
            connection.request(
                "POST", path, body=BODY, headers={"Content-Type": "application/json"}
            )
            response = connection.getresponse()
            body = response.read()
            content = json.loads(body)["choices"][0]["message"]["content"]
            return response.status == 200 and bool(content)
        except Exception:
            local.connection = None
            return False

    points = []
    for jobs, requests in request["levels"]:
        local = threading.local()
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            started = time.perf_counter()
            results = list(pool.map(one, range(requests)))
            elapsed = time.perf_counter() - started
        rate = requests / elapsed
        ideal = jobs / latency
        points.append(
            {
                "jobs": jobs,
                "requests": requests,
                "failures": results.count(False),
                "elapsed_ms": elapsed * 1e3,
                "requests_per_second": rate,
                "ideal_requests_per_second": ideal,
                "fraction_of_ideal": rate / ideal,
            }
        )
    json.dump({"python": sys.version.split()[0], "throughput": points}, sys.stdout)


main()
