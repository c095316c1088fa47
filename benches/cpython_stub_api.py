"""A stub of the contphy-eval scene API for CPython, used by `contphy-eval bench sandbox`.

It mirrors the names and signatures of the real API (SoftScene, find, query_single, query_pair,
query_both, register_event/event, init_dyn_simulation, happen, bool_to_yesno) and returns fixed
values, so the benchmark times the interpreter running the same program text, not the scene.
The harness below reads a JSON list of programs on stdin and prints timing JSON on stdout.
"""

import json
import sys
import time


class SceneApiError(Exception):
    pass


class SceneObject:
    def __init__(self, name):
        self.name = name

    def __repr__(self):
        return "SceneObject(%r)" % self.name


class SceneEvent:
    def __init__(self, objects, action, attribute):
        self.objects, self.action, self.attribute = objects, action, attribute


class SoftDynamicScene:
    def __init__(self, scene, event):
        self.scene, self.event = scene, event

    def happen(self, scene_objects, action, target=""):
        return action == "motion" and target == "up"


class SoftScene:
    def __init__(self, video, scene_name, start_frame=0, end_frame=-1, mode=None, video_id=None):
        self.scene_name = scene_name

    def find(self, object_name):
        return [SceneObject(object_name)]

    def query_single(self, prop, obj):
        return 0.2

    def query_pair(self, prop, first, second):
        return (0.2, 0.25)

    def register_event(self, scene_objects, action, attribute=""):
        return SceneEvent(scene_objects, action, attribute)

    event = register_event

    def init_dyn_simulation(self, event):
        return SoftDynamicScene(self, event)


def query_both(prop, first, second):
    return (0.2, 0.25)


def bool_to_yesno(value):
    return "yes" if value else "no"


def main():
    request = json.load(sys.stdin)
    programs, rounds = request["programs"], request["rounds"]
    api = {
        "SoftScene": SoftScene, "SceneObject": SceneObject, "SceneEvent": SceneEvent,
        "SoftDynamicScene": SoftDynamicScene, "SceneApiError": SceneApiError,
        "bool_to_yesno": bool_to_yesno, "query_both": query_both,
    }
    per_program_ns = []
    for source in programs:
        best = None
        for _ in range(rounds):
            started = time.perf_counter_ns()
            code = compile(source, "<program>", "exec")
            scope = dict(api)
            scope["video"] = object()
            exec(code, scope)
            if "execute_command" in scope:
                scope["execute_command"](scope["video"])
            elapsed = time.perf_counter_ns() - started
            best = elapsed if best is None else min(best, elapsed)
        per_program_ns.append(best)
    json.dump({"version": sys.version.split()[0], "per_program_ns": per_program_ns}, sys.stdout)


if __name__ == "__main__":
    main()
