# Is the tension of the green rope equal to that of the purple rope?
# expected: can not answer

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    green_rope = rope_scene.find("green rope")
    purple_rope = rope_scene.find("purple rope")

    green_tension, purple_tension = rope_scene.query_pair('tension', green_rope, purple_rope)

    if green_tension is None or purple_tension is None:
        return "can not answer"
    # Values are floats: "equal" means equal within a small tolerance.
    return bool_to_yesno(abs(green_tension - purple_tension) < 1e-5)
