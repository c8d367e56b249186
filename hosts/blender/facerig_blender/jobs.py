"""Operators whose facerig work runs off Blender's main thread, with progress and Esc to cancel.

An operator here splits its work in three: prepare() on the main thread reads
the scene and checks the input (raising UserError), returning a Job; the
Job's work(progress) makes facerig calls only (no bpy), on a worker thread
when the operator was invoked from the UI, on the main thread from scripts
and in background mode (execute); the Job's apply() writes the result into
the scene on the main thread. Nothing in the scene changes before apply(),
so a failure or a cancel leaves it as it was, and the one undo step of a
finished operator takes the whole change back.
"""
import threading
import traceback
from dataclasses import dataclass, field
from typing import Any, Callable

import bpy

from . import library


class UserError(Exception):
    """A problem with the user's input or scene, reported as it is."""


# prepare() may keep data-blocks (objects, the scene) for apply(), never the context: the one an
# operator's invoke() receives is not valid in later modal() calls. A data-block deleted meanwhile
# raises ReferenceError, which _finish reports.


@dataclass
class Job:
    title: str                               # "Building face shapes", for the status bar
    work: Callable[[Callable], Any]          # work(progress) -> result; progress(stage, done, total) -> stop?
    apply: Callable[[Any], str]              # apply(result) -> the message reported when done
    cleanup: Callable[[], None] = field(default=lambda: None)


def _facerig_errors():
    try:
        return (library.facerig().FacerigError,)
    except library.MissingLibraryError:
        return ()


def _message(error):
    """What the user reads: the message itself, no traceback."""
    text = str(error).strip() or type(error).__name__
    return text if len(text) < 600 else text[:600] + "..."


class Progress:
    """The worker's latest stage, read by the main thread; `cancelled` stops the work."""

    def __init__(self):
        self.stage, self.done, self.total = "", 0, 0
        self.cancelled = False

    def __call__(self, stage, done, total):
        self.stage, self.done, self.total = stage, done, total
        return self.cancelled

    def text(self, title):
        step = f" {self.done}/{self.total}" if self.total else ""
        return f"facerig: {title}" + (f" - {self.stage}{step}" if self.stage else "") + "  (Esc to cancel)"


class JobOperator:
    """Mixin for bpy.types.Operator: subclasses define prepare(context) -> Job."""

    def prepare(self, context):
        raise NotImplementedError

    def _start(self, context):
        try:
            return self.prepare(context)
        except (UserError, library.MissingLibraryError, *_facerig_errors()) as error:
            self.report({"ERROR"}, _message(error))
        except Exception as error:  # a bug: the user gets the message, the console the traceback
            traceback.print_exc()
            self.report({"ERROR"}, f"facerig: {_message(error)} (details in the system console)")
        return None

    def _finish(self, job, run):
        """Runs run() (the work) and applies its result, reporting any failure; the operator's return."""
        try:
            message = job.apply(run())
        except (UserError, library.MissingLibraryError, *_facerig_errors()) as error:
            self.report({"ERROR"}, _message(error))
            return {"CANCELLED"}
        except ReferenceError:
            self.report({"ERROR"}, "facerig: an object it was working on was deleted meanwhile")
            return {"CANCELLED"}
        except Exception as error:  # a bug: the user gets the message, the console the traceback
            traceback.print_exc()
            self.report({"ERROR"}, f"facerig: {_message(error)} (details in the system console)")
            return {"CANCELLED"}
        finally:
            job.cleanup()
        if message:
            self.report({"INFO"}, message)
        return {"FINISHED"}

    def execute(self, context):
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        window_manager = context.window_manager
        window_manager.progress_begin(0, 1)
        try:
            return self._finish(job, lambda: job.work(Progress()))
        finally:
            window_manager.progress_end()

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        self._worker = Worker(job)
        self._timer = context.window_manager.event_timer_add(0.1, window=context.window)
        context.window_manager.modal_handler_add(self)
        context.workspace.status_text_set(self._worker.status())
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._worker.cancel()
        if event.type != "TIMER":
            return {"RUNNING_MODAL"} if event.type == "ESC" else {"PASS_THROUGH"}
        if self._worker.running():
            context.workspace.status_text_set(self._worker.status())
            return {"RUNNING_MODAL"}
        context.window_manager.event_timer_remove(self._timer)
        context.workspace.status_text_set(None)
        return self._finish(self._worker.job, self._worker.result)


class Worker:
    """A job's work(progress) on a thread of its own (the facerig calls release Python's lock), polled
    by the main thread: running(), status() for the status bar, cancel() (the ABI's progress
    callback then stops the work), result() once done (raising what the work raised)."""

    def __init__(self, job):
        self.job, self.progress, self._outcome = job, Progress(), {}
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        try:
            self._outcome["result"] = self.job.work(self.progress)
        except BaseException as error:  # raised again on the main thread, by result()
            self._outcome["error"] = error

    def running(self):
        return self._thread.is_alive()

    def status(self):
        return self.progress.text(self.job.title)

    def cancel(self):
        self.progress.cancelled = True

    def result(self):
        self._thread.join()
        if "error" in self._outcome:
            raise self._outcome["error"]
        return self._outcome["result"]
