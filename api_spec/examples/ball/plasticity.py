# Is the plasticity of the red ball much greater than the green ball?
# expected: no

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    red_ball = ball_scene.find("red ball")
    green_ball = ball_scene.find("green ball")

    red_plasticity, green_plasticity = ball_scene.query_pair('plasticity', red_ball, green_ball)

    if red_plasticity is None or green_plasticity is None:
        return "can not answer"
    return bool_to_yesno(red_plasticity > green_plasticity)
