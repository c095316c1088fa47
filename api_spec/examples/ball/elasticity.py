# Is the elasticity of the red ball much greater than the blue ball?
# expected: yes

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    red_ball = ball_scene.find("red ball")
    blue_ball = ball_scene.find("blue ball")

    # query_pair knows whether the two balls' materials can be compared.
    red_elasticity, blue_elasticity = ball_scene.query_pair('elasticity', red_ball, blue_ball)

    if red_elasticity is None or blue_elasticity is None:
        return "can not answer"
    return bool_to_yesno(red_elasticity > blue_elasticity)
