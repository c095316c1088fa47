# If we removed the red floating wall and other balls, which pit would the black ball drop into?
# runnable: no (the paper's listing eg4; ball scenes have no backend in this version)

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    black_ball = ball_scene.find("black ball")
    pits = ball_scene.find("pit")

    cf_init_event = ball_scene.register_event([], "remove", "red floating wall and other balls")
    ball_cf_scene = ball_scene.init_dyn_simulation(cf_init_event)

    for pit in pits:
        if ball_cf_scene.happen([black_ball], "droping", pit):
            # An answer is text: return the pit's name, not the object.
            return pit.name

    return "can not answer"
