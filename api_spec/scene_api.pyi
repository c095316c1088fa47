"""The ContPhy scene API (ContPRO, ICML 2024, listing "Full API"), as this evaluator binds it.

A program answers one question about one video. It defines `execute_command(video)`; the
evaluator calls it with the `video` below and scores the value it returns. Everything in this
file is already defined: do not import it. The only importable module is `math`; files, the
network, `eval`/`exec`/`open`/`getattr`/`dir` and names starting with `_` are unavailable.

Scenarios and their objects (the words `SoftScene.find` understands):

- rope:  cube, sphere, pulley (solid or hollow, static or dynamic), rope, fixed point
- fluid: fluid, container, stick, emitter (a first or a later emitter)
- cloth: cloth, pillar, plate
- ball:  ball, stick, pit, floating wall, ramp

All four scenarios can be answered by this version. Cloth videos are answered from their
annotations only: with perception from pixels or simulated dynamics every cloth call raises
`SceneUnavailableError`. The signatures below are the paper's for all four scenarios, plus
`SoftDynamicScene.final_pose` for the end pose of a cloth scene's pillars and plates.

Errors: a wrong call (unknown word, unknown property or action, an empty list where one object
is needed, a wrong argument type) raises `SceneApiError` with a message that says what is
allowed. A program should not catch it: fix the call instead.
"""

class SceneApiError(Exception):
    """Raised when the API is called wrongly; the message says what is allowed."""

class SceneUnavailableError(SceneApiError):
    """The call is well formed but this video cannot answer it (for example a scenario without a
    backend, or a counterfactual run the video does not have)."""

class SceneNotSeenError(SceneUnavailableError):
    """The name is well formed but no object read from the video's pixels carries it (perception
    from pixels only): the detector missed the object or read it in another colour."""

class SceneDataError(SceneApiError):
    """The video's files are missing or broken."""

class Video:
    """The video a program is given: `execute_command(video)` receives the global `video`.

    It cannot be created by a program; pass it to `SoftScene(video, scene_name)`.
    """

    video_id: str
    """The video's id (its folder name), e.g. '0'."""

    scene_name: str
    """The video's scenario: 'rope', 'fluid', 'cloth' or 'ball'."""

video: Video
"""The video of the question."""

class SceneObject:
    """One object of the scene, as `SoftScene.find` returns it.

    Objects compare equal when they are the same object, and can be put in sets and dict keys.
    Text attributes are lower case.
    """

    name: str
    """The short name used in questions, e.g. 'purple cube', 'blue solid pulley', 'green rope',
    'pink fluid', 'yellow later emitter'."""

    full_name: str
    """The annotation name, e.g. 'Blue Solid Static Pulley (0 1)', 'Later Emitted Yellow Fluid
    Emitter'."""

    color: str
    """Colour words, e.g. 'blue', 'light blue'."""

    kind: str
    """The object class: rope scenes have 'cube', 'sphere', 'pulley', 'rope', 'fixed point';
    fluid scenes 'fluid', 'container', 'stick', 'emitter'; cloth scenes 'cloth', 'pillar',
    'plate'; ball scenes 'ball', 'floating wall', 'ramp', 'pit'."""

    type: str
    """The same as `kind` (the paper's name for it)."""

    shape: str | None
    """Rope scenes. Pulleys: 'solid' (the small ones) or 'hollow' (the big ones); None for other
    objects."""

    dynamic: str
    """Rope scenes. 'dynamic' for loads (cubes, spheres), ropes and movable pulleys; 'static' for
    static pulleys and fixed points."""

    emission: str | None
    """Fluid scenes. Emitters: 'first' for the emitter that pours its fluid from the start of
    the video, 'later' for a fluid's second emitter, which opens near the end of the video (the
    questions' "the other yellow emitter"); None for other objects."""

    side: str | None
    """Ball scenes. Pits and ramps: 'left' or 'right' (pits have no colour: their names are
    'left pit' and 'right pit'; a ramp's is e.g. 'yellow left ramp'); None for other objects.
    Cloth scenes. The cloths: 'left' or 'right' (they have no colour: their names are 'left
    cloth' and 'right cloth'); None for pillars and plates."""

class SceneEvent:
    """An event registered with `SoftScene.register_event`; pass it to
    `SoftScene.init_dyn_simulation`. It cannot be created directly."""

class SoftScene:
    """A soft scene (rope/fluid/cloth/ball) of one video and the objects in it.

    The paper's attributes `video`, `frm_num` and `simulation` are internal and not exposed.
    """

    scene_name: str
    """The name of the scene: 'rope', 'fluid', 'cloth' or 'ball'."""

    mode: str
    """'online' or 'offline'. This evaluator answers from pre-computed (offline) annotations."""

    vid: str
    """The video id."""

    start_frame: int
    """The first frame given to the constructor (0 by default)."""

    end_frame: int
    """The end frame given to the constructor (-1, the end of the video, by default)."""

    all_event_actions: list[str]
    """The actions `register_event` knows: ['increase', 'decrease', 'emit', 'remove', 'simulate']."""

    def __init__(
        self,
        video: Video,
        scene_name: str,
        start_frame: int = 0,
        end_frame: int = -1,
        mode: str | None = None,
        video_id: str | None = None,
    ) -> None:
        """Opens the scene of `video`.

        Parameters
        ----------
        video : Video
            The `video` given to `execute_command`.
        scene_name : str
            'rope', 'fluid', 'cloth' or 'ball'; must be the video's scenario, otherwise
            `SceneApiError` ('this video is a rope scene, not `fluid`').
        start_frame, end_frame : int
            Frame range; the default is the whole video.
        mode : str | None
            'online' or 'offline'; None means 'offline'.
        video_id : str | None
            If given, must be the video's id.

        Nothing is loaded until the first query, so opening a scene is free.

        Examples
        --------
        >>> rope_scene = SoftScene(video, 'rope')
        """

    def find(self, object_name: str) -> list[SceneObject]:
        """Returns the objects matching every word of `object_name`, in a fixed scene order;
        an empty list when none matches.

        Words understood (case-insensitive, plurals allowed, 'the'/'a'/'any'/'object(s)'
        ignored):
        - colours: red, orange, yellow, green, cyan, blue, purple, pink, brown, gray (or grey),
          black, white, light blue, light green, light yellow, light coral, light purple.
          Colours match exactly: 'blue' does not find a 'light blue' object.
        - kinds: the scenario's objects (rope: cube, sphere, pulley, rope, fixed point, and
          'load' means a cube or a sphere; fluid: fluid, container, stick, emitter; cloth:
          cloth, pillar, plate; ball: ball, floating wall, ramp, pit, and stick, which finds
          nothing in ball scenes). A kind of another scenario ('container' in a rope scene)
          finds nothing.
        - rope pulley shapes: solid (also small, little), hollow (also big, large); a shape
          alone means a pulley.
        - rope dynamics: static, dynamic (also movable).
        - a rope grid id `(layer column)` at the end, as in full names: 'blue pulley (0 1)'.
        - fluid emitter emissions: first (also original), later (also other, second,
          predictive); an emission alone means an emitter. 'the other yellow emitter' is the
          yellow fluid's later emitter; 'yellow emitter' finds both of its emitters.
        - ball pit and ramp sides: left, right; a side alone means a pit ('left pit',
          'yellow left ramp').
        - cloth sides: left, right; a side alone means a cloth ('left cloth'). Pillars and
          plates are found by colour and kind ('green plate', 'light blue pillar').
        Any other word raises `SceneApiError` listing the vocabulary; so does naming two
        different colours or kinds in one call (find one description at a time).

        Parameters
        ----------
        object_name : str
            A description such as 'purple cube', 'blue solid pulley', 'rope', 'green', ''.
            An empty string finds every object.

        Returns
        -------
        list[SceneObject]
            The matching objects; `len(...)` counts them.

        Examples
        --------
        >>> # How many blue objects are there in the video?
        >>> blue_objects = rope_scene.find("blue")
        >>> return len(blue_objects)

        >>> # Is there any gray hollow pulley in the video?
        >>> return bool_to_yesno(len(rope_scene.find("gray hollow pulley")) > 0)

        >>> # How many sticks are there in the video?
        >>> return len(fluid_scene.find("stick"))
        """

    def query_single(self, property: str, object: SceneObject | list[SceneObject]) -> float | None:
        """Returns one property value of one object, or None when the video cannot tell it.

        Call `query_pair` instead of calling this twice when comparing two objects: only
        `query_pair` knows whether the two values can be compared.

        Parameters
        ----------
        property : str
            'mass', 'tension', 'density', 'elasticity', 'plasticity' or 'bending'.
            Rope scenes have:
            - 'mass' of a cube or sphere, in kg (the benchmark's nominal mass, e.g. 0.15, 0.2,
              0.25; a load hanging under a movable pulley reads about double, e.g. 0.4);
            - 'tension' of a rope, in N: the weight (m * 9.81) of the load the rope carries;
              None when the rope carries loads of different masses or none.
            Fluid scenes have 'density' of a fluid, in kg/m³ (e.g. 1600, 3000, 4400).
            Ball scenes have 'elasticity' and 'plasticity' of a ball, scores of its material:
            elasticity 1 for the elastic ball, 0 for the rigid and the plastic one; plasticity
            1 for the plastic ball, 0 for the others. `query_pair` gives (None, None) for two
            balls whose materials do not order them (rigid and plastic on elasticity, elastic
            and rigid on plasticity).
            Cloth scenes have 'elasticity' and 'bending' of a cloth, the values the video was
            made with: elasticity is how much the cloth stretches (0.011 for the stretchy
            cloth, 0 for the one that does not stretch); bending is how easily it bends and
            wrinkles (0.035 bends easily, 0.013 is stiffer), so a cloth "harder to bend" has
            the smaller bending. The two cloths always differ in both and always compare.
            Other properties, or mass of a pulley or rope, tension of a non-rope, density of a
            non-fluid, elasticity or bending of a pillar or plate, raise `SceneApiError`.
        object : SceneObject | list[SceneObject]
            One object, or the list `find` returned holding exactly one object (an empty list
            or a list of two raises `SceneApiError`).

        Returns
        -------
        float | None
        """

    def query_pair(
        self,
        property: str,
        object1: SceneObject | list[SceneObject],
        object2: SceneObject | list[SceneObject],
    ) -> tuple[float | None, float | None]:
        """Returns the property values of two objects to be compared, or (None, None) when the
        video cannot compare them.

        Rope scenes: two loads (or two ropes) can be compared only when they hang in the same
        mechanically coupled rope-pulley group; across groups the result is (None, None) and
        the question's answer is "can not answer". Fluid scenes: two fluids' densities can be
        compared only when the video shows how they layer (they settle in one container, or
        are linked through a chain of such pairs); otherwise (None, None), "can not answer".
        Same properties, units and object rules as `query_single`.

        Parameters
        ----------
        property : str
            The property, e.g. 'mass' or 'tension'.
        object1, object2 : SceneObject | list[SceneObject]
            The two objects (each one object, or a one-object list as `find` returns).

        Returns
        -------
        tuple[float | None, float | None]
            Both values, or (None, None).

        Examples
        --------
        >>> # Is the mass of the green cube greater than half that of the purple cube?
        >>> green_mass, purple_mass = rope_scene.query_pair('mass', rope_scene.find("green cube"), rope_scene.find("purple cube"))
        >>> if green_mass is None or purple_mass is None:
        >>>     return "can not answer"
        >>> return bool_to_yesno(green_mass > 0.5 * purple_mass)

        >>> # Is the fluid density of the pink fluid greater than that of the yellow fluid?
        >>> pink_density, yellow_density = fluid_scene.query_pair('density', fluid_scene.find("pink fluid"), fluid_scene.find("yellow fluid"))
        >>> if pink_density is None or yellow_density is None:
        >>>     return "can not answer"
        >>> return bool_to_yesno(pink_density > yellow_density)
        """

    def register_event(
        self,
        scene_objects: SceneObject | list[SceneObject],
        action: str,
        attribute: str | SceneObject | list[SceneObject] = "",
    ) -> SceneEvent:
        """Creates the event that starts a dynamic scene (counterfactual, goal-driven or
        predictive); pass the result to `init_dyn_simulation`.

        Parameters
        ----------
        scene_objects : SceneObject | list[SceneObject]
            The object the event changes (at most one), or [] for 'simulate' and 'remove'.
        action : str
            One of `all_event_actions`: 'increase', 'decrease', 'emit', 'remove', 'simulate'.
            Rope scenes support:
            - 'increase' / 'decrease' with attribute 'mass' and one cube or sphere: the
              counterfactual "if the <load> were much heavier / lighter";
            - 'simulate' with [] and attribute '': the factual future of the video.
            'emit' (fluid) and 'remove' (fluid sticks, ball floating walls) raise
            `SceneApiError` in rope scenes.
            Fluid scenes support:
            - 'remove' with [] and a stick's description ('green stick'), or with the stick as
              the object and attribute 'stick': the counterfactual "if the green stick were
              removed";
            - 'emit' with an emitter and attribute 'fluid': the future in which that emitter
              pours its fluid ("the fluid from the other yellow emitter": the emitter
              `find("other yellow emitter")`); in that dynamic scene the fluid of the
              emitter's colour is the fluid it emits;
            - 'simulate' with [] and attribute '': the factual future of the video.
            Ball scenes support:
            - 'remove' with [] and a floating wall's description ('red floating wall and
              other balls', or 'red floating wall'), or with the wall as the object: the
              counterfactual "if we removed the red floating wall and other balls", in which
              the ball `happen` asks about falls alone;
            - 'simulate' with [] and attribute '': the factual future of the video.
            Cloth scenes support 'simulate' with [] and attribute '' only: the future of the
            video, in which the cloth is pulled over the pillars and plates and released.
            A removal the video has no record of raises `SceneUnavailableError`.
        attribute : str | SceneObject | list[SceneObject]
            What changes: 'mass' for increase/decrease, '' for simulate, 'fluid' for emit; for
            'remove' a description such as 'green stick' (or the objects).

        Returns
        -------
        SceneEvent

        Examples
        --------
        >>> # If the purple cube were much lighter, ...
        >>> cf_init_event = rope_scene.register_event(rope_scene.find("purple cube"), "decrease", "mass")
        >>> rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)

        >>> # If we want the green cube to move down, what can we do? | Increase the mass of the pink sphere
        >>> gd_init_event = rope_scene.register_event(rope_scene.find("pink sphere"), "increase", "mass")
        >>> rope_gd_scene = rope_scene.init_dyn_simulation(gd_init_event)

        >>> # If the brown stick were removed, ...
        >>> cf_init_event = fluid_scene.register_event([], "remove", "brown stick")

        >>> # Which stick will the fluid from the other yellow emitter pass?
        >>> pred_init_event = fluid_scene.register_event(fluid_scene.find("other yellow emitter"), "emit", "fluid")

        >>> # If we removed the red floating wall and other balls, ...
        >>> cf_init_event = ball_scene.register_event([], "remove", "red floating wall and other balls")
        """

    def event(
        self,
        scene_objects: SceneObject | list[SceneObject],
        action: str,
        attribute: str | SceneObject | list[SceneObject] = "",
    ) -> SceneEvent:
        """The same as `register_event` (the paper's examples use both names)."""

    def init_dyn_simulation(self, dyn_init_event: SceneEvent) -> SoftDynamicScene:
        """Starts the dynamic scene (predictive, counterfactual or goal-driven) that
        `dyn_init_event` describes.

        Parameters
        ----------
        dyn_init_event : SceneEvent
            The event `register_event` returned.

        Returns
        -------
        SoftDynamicScene
        """

class SoftDynamicScene:
    """The dynamic scene started by an event: the same objects as its `SoftScene`, with the
    event's outcome. Created by `SoftScene.init_dyn_simulation`, not directly."""

    scene_name: str
    """The scene's name, as in its SoftScene."""

    all_dyn_actions: list[str]
    """The actions `happen` knows: ['entering', 'passing', 'motion', 'rotation', 'collision',
    'falling', 'touching', 'droping']."""

    def happen(
        self,
        scene_objects: SceneObject | list[SceneObject],
        action: str,
        target: str | SceneObject | list[SceneObject] = "",
    ) -> bool:
        """Whether `action` (with `target`) happens to the object in this dynamic scene.

        Parameters
        ----------
        scene_objects : SceneObject | list[SceneObject]
            Exactly one object, e.g. `[green_cube]` or the one-object list `find` returned.
        action : str
            One of `all_dyn_actions`. Rope scenes answer:
            - 'motion' of a cube, sphere, pulley or fixed point, target 'up', 'down' or
              'stationary' (does not move);
            - 'rotation' of a pulley, target 'clockwise', 'anti-clockwise' or 'stationary'
              (does not rotate).
            Ropes have no motion result; only pulleys rotate. 'entering', 'passing',
            'collision', 'falling', 'touching', 'droping' belong to the other scenarios and
            raise `SceneApiError` in rope scenes.
            Fluid scenes answer, for a fluid (or an emitter, standing for the fluid it pours):
            - 'passing' a stick: the fluid flows over the stick;
            - 'entering' a container: some of the fluid ends in it;
            - 'entering most' a container: more of the fluid ends in it than in any other
              container ("let most of the pink fluid enter the gray container").
            The fluid of a later emitter does not flow in 'remove' scenes (the video's
            counterfactual runs pour the first emitters only).
            Ball scenes answer 'droping' for a ball and a pit: the ball finally drops into that
            pit (during the video or after it).
            Cloth scenes answer, for a pillar or plate (the cloths themselves are not asked
            about):
            - 'falling' with target '': the box falls over (it ends lying on a side or upside
              down, not standing upright). A box that ends leaning, its top still pointing up,
              has neither clearly fallen nor stayed up: 'falling' raises
              `SceneUnavailableError` for it (its `final_pose` still answers);
            - 'collision' with another pillar or plate as the target: the two boxes collide at
              some point in the video;
            - 'touching' with another pillar or plate as the target: the two boxes are in
              touch at the end.
            To relate two boxes, pass the first as the object and the second as the target,
            `happen([green_plate], 'touching', [gray_pillar])`, not both as the objects.
        target : str | SceneObject | list[SceneObject]
            A direction word (rope), a description ('red container') or objects (fluid, ball
            and cloth targets such as `[black_container]`: one stick or container in fluid
            scenes, one pillar or plate in cloth scenes); may be ''.

        Returns
        -------
        bool
            True if it happens.

        Examples
        --------
        >>> # If the purple cube were much heavier, which direction would the blue pulley rotate? | Clockwise
        >>> cf_init_event = rope_scene.register_event(rope_scene.find("purple cube"), "increase", "mass")
        >>> rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)
        >>> return bool_to_yesno(rope_cf_scene.happen(rope_scene.find("blue pulley"), "rotation", "clockwise"))

        >>> # If the brown stick were removed, which container would pink fluid flow into? | Green container
        >>> cf_init_event = fluid_scene.register_event([], "remove", "brown stick")
        >>> fluid_cf_scene = fluid_scene.init_dyn_simulation(cf_init_event)
        >>> return bool_to_yesno(fluid_cf_scene.happen(fluid_scene.find("pink fluid"), "entering", fluid_scene.find("green container")))

        >>> # Is the green plate finally in touch with the gray pillar? | Yes
        >>> pred_init_event = cloth_scene.register_event([], "simulate", "")
        >>> cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)
        >>> return bool_to_yesno(cloth_pred_scene.happen(cloth_scene.find("green plate"), "touching", cloth_scene.find("gray pillar")))
        """

    def final_pose(self, scene_object: SceneObject | list[SceneObject]) -> str:
        """How the object ends in this dynamic scene, in the words of the pose questions.

        Cloth scenes only: the end pose of a pillar or plate, one of these five phrases,
        spelled exactly so (the options of "Which phrase below can best describe the final
        pose of ...?"):
        - 'It stands upright': it stands as it was placed;
        - 'It leans at an angle, its top still pointing up': tilted, for example resting on
          a neighbour;
        - 'It lies flat on its back, front or side';
        - 'It is tilted upside down at an angle, its top pointing down';
        - 'It stands upside down on its top'.
        A cloth, or an object of another scenario, raises `SceneApiError`.

        Parameters
        ----------
        scene_object : SceneObject | list[SceneObject]
            One pillar or plate, or the one-object list `find` returned.

        Returns
        -------
        str
            One of the five phrases.

        Examples
        --------
        >>> # Which phrase below can best describe the final pose of the green plate? | It stands upright
        >>> pred_init_event = cloth_scene.register_event([], "simulate", "")
        >>> cloth_pred_scene = cloth_scene.init_dyn_simulation(pred_init_event)
        >>> return bool_to_yesno(cloth_pred_scene.final_pose(cloth_scene.find("green plate")) == "It stands upright")
        """

def bool_to_yesno(bool_answer: object, /) -> str:
    """Returns 'yes' if `bool_answer` is true (Python truthiness), otherwise 'no'.

    Examples
    --------
    >>> bool_to_yesno(3 > 2)
    'yes'
    """

def query_both(
    property: str,
    object1: SceneObject | list[SceneObject],
    object2: SceneObject | list[SceneObject],
) -> tuple[float | None, float | None]:
    """`query_pair` on the program's video without naming the scene (the paper's listing calls it
    this way): `query_both('mass', sphere, black_cube)`."""
